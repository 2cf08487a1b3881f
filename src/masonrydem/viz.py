"""3-D state and pictures with pyvista/VTK, off screen.

Off-screen rendering uses VTK's EGL window with Mesa (no X server needed):
VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow, pyvista.OFF_SCREEN = True.
"""
import os

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import pyvista as pv  # noqa: E402

from . import kernels as K  # noqa: E402
from .solver import zone_damage  # noqa: E402

pv.OFF_SCREEN = True


def zones_grid(specimen, state=None):
    """UnstructuredGrid of the units in the initial geometry: the
    tetrahedra of zone blocks (only the first overlay of each cell: the two
    fill the same cell) and the hexahedra of linear-cell blocks, with point
    data 'u' (displacement, m) and cell data 'damage' (tensile, 0..1: the
    cell's volume-weighted mean; 0 in elastic cells) and 'unit'
    (1-based)."""
    a = specimen.assembly
    nb = a.n - len(a.strips)
    tets = a.zones.tets
    first = (np.arange(tets.shape[0]) % 10) < 5
    hexes = a.cells.nodes[:, [0, 1, 3, 2, 4, 5, 7, 6]]          # VTK's corner order
    cells = np.concatenate([np.hstack([np.full((first.sum(), 1), 4), tets[first]]).ravel(),
                            np.hstack([np.full((hexes.shape[0], 1), 8), hexes]).ravel()])
    types = np.concatenate([np.full(first.sum(), pv.CellType.TETRA), np.full(hexes.shape[0], pv.CellType.HEXAHEDRON)])
    grid = pv.UnstructuredGrid(cells, types, a.nodes.x0[:nb])
    unit = specimen.block_unit + 1
    grid.cell_data["unit"] = np.concatenate([np.repeat(unit, np.diff(a.zone_ptr))[first],
                                             np.repeat(unit, np.diff(a.cell_ptr))])
    grid.point_data["u"] = state.nodes.u[:nb] if state is not None else np.zeros((nb, 3))
    if state is not None:
        d = zone_damage(state)
        w = a.zones.vol * a.zones.wt
        with np.errstate(invalid="ignore"):
            zd = np.repeat((d * w).reshape(-1, 10).sum(axis=1) / w.reshape(-1, 10).sum(axis=1), 5)
        grid.cell_data["damage"] = np.concatenate([zd, np.zeros(hexes.shape[0])])
    return grid


def joints_points(specimen, state):
    """PolyData of the joint sub-contacts (on side A, initial geometry) with
    point data 'u' (displacement of side A), 'damage' (D), 'joint'
    (1-based) and 'area'."""
    a = specimen.assembly
    j = a.joints
    n = j.area.size
    pts = np.zeros((n, 3))
    disp = np.zeros((n, 3))
    for k in range(4):
        mask = k < j.cnt[:, 0]
        w = j.w[mask, k, None]
        pts[mask] += w * a.nodes.x0[j.nodes[mask, k]]
        disp[mask] += w * state.nodes.u[j.nodes[mask, k]]
    poly = pv.PolyData(pts)
    joint = np.zeros(n, int)
    for c, jn in zip(a.contacts, specimen.contact_joint):
        joint[c.sc] = jn + 1
    poly.point_data["u"] = disp
    poly.point_data["joint"] = joint
    poly.point_data["area"] = j.area
    poly.point_data["damage"] = state.joints.state[:, K.JS_D]
    return poly


def state_blocks(specimen, state):
    """The final state, readable by ParaView and pyvista: MultiBlock
    {zones, joints} in the initial geometry with the displacement 'u' as
    point data (ParaView: Warp By Vector)."""
    return pv.MultiBlock({"zones": zones_grid(specimen, state),
                          "joints": joints_points(specimen, state)})


def _camera(p, back=False):
    """Front (y = 0, load side) or back (y = t, the tension face in
    bending) view, slightly from above."""
    eye = (0.9, 1.7, 0.9) if back else (0.2, -1.6, 1.0)
    p.camera_position = [eye, (0.54, 0.057, 0.225), (0, 0, 1)]
    p.camera.zoom(1.25)


def picture_numbering(specimen, path, window=(1600, 1000)):
    """The model with its units (U1..) and joints (J1..) numbered."""
    a = specimen.assembly
    p = pv.Plotter(off_screen=True, window_size=window)
    grid = zones_grid(specimen)
    p.add_mesh(grid, scalars="unit", cmap="tab20", show_scalar_bar=False)
    labels_u, pos_u = [], []
    for u in range(len(specimen.units)):
        blks = [blk for blk in a.blocks if specimen.block_unit[blk.id] == u]
        lo, hi = blks[0].lo, blks[-1].hi
        pos_u.append([(lo[0] + hi[0]) / 2, lo[1] - 0.002, (lo[2] + hi[2]) / 2])
        labels_u.append(f"U{u + 1}")
    p.add_point_labels(np.array(pos_u), labels_u, font_size=14, point_size=1, shape_color="white",
                       always_visible=True)
    pos_j = np.zeros((len(specimen.joints), 3))
    area = np.zeros(len(specimen.joints))
    for c, jn in zip(a.contacts, specimen.contact_joint):
        ba, bb = a.blocks[c.block_a], a.blocks[c.block_b]
        lo, hi = np.maximum(ba.lo, bb.lo), np.minimum(ba.hi, bb.hi)
        pos_j[jn] += c.area * (lo + hi) / 2
        area[jn] += c.area
    pos_j /= area[:, None]
    pos_j[:, 1] = -0.004
    p.add_point_labels(pos_j, [f"J{j + 1}" for j in range(len(specimen.joints))], font_size=11,
                       point_size=6, point_color="red", text_color="darkred", shape_opacity=0.6,
                       always_visible=True)
    p.add_text(f"{specimen.scene.name}: {len(specimen.units)} units (U), {len(specimen.joints)} joints (J)",
               font_size=12)
    _camera(p)
    p.screenshot(str(path))
    p.close()


def picture_damage(state, path, title="", magnify=None, window=(1600, 1000)):
    """The cracked, deformed state (a MultiBlock from ``state_blocks`` or
    read from state.vtm): zones coloured by tensile damage (cells with
    damage >= 0.5 solid), joint sub-contacts by joint damage; displacements
    magnified (by default so that the largest is 3 % of the wall length).
    Returns the magnification."""
    zones, joints = state["zones"], state["joints"]
    if magnify is None:
        umax = float(np.abs(zones.point_data["u"]).max())
        magnify = 0.03 * float(np.ptp(zones.points[:, 0])) / umax if umax > 0 else 1.0
    zones = zones.warp_by_vector("u", factor=magnify)
    joints = joints.warp_by_vector("u", factor=magnify)
    p = pv.Plotter(off_screen=True, window_size=window)
    p.add_mesh(zones, scalars="damage", cmap="Reds", clim=(0, 1), opacity=0.35, show_edges=False,
               scalar_bar_args=dict(title="brick tensile damage", vertical=True, position_x=0.02,
                                    position_y=0.25, height=0.5))
    cracked = zones.threshold(0.5, scalars="damage")
    if cracked.n_cells:
        p.add_mesh(cracked, color="darkred", show_scalar_bar=False)
    p.add_mesh(joints, scalars="damage", cmap="viridis", clim=(0, 1), point_size=12,
               render_points_as_spheres=True,
               scalar_bar_args=dict(title="joint damage D", vertical=True, position_x=0.9,
                                    position_y=0.25, height=0.5))
    p.add_text(f"{title}  (back face, tension side; displacements x {magnify:.0f}; "
               f"cells with damage >= 0.5 solid)", font_size=11)
    _camera(p, back=True)
    p.screenshot(str(path))
    p.close()
    return magnify
