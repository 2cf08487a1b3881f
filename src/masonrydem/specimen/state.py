"""The final state of a run as VTK data (pyvista), readable by ParaView:
the units' zones and cells with their displacement and damage, and the
joints' sub-contacts.  Written by ``masonrydem run --state``; the report
draws pictures of it (report/pictures.py)."""
import os

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import pyvista as pv  # noqa: E402

from ..dem import JS_D, zone_damage  # noqa: E402


def zones_grid(specimen, state=None):
    """UnstructuredGrid of the units in the initial geometry: the
    tetrahedra of zone blocks (only the first overlay of each cell: the two
    fill the same cell) and the hexahedra of linear-cell blocks, with point
    data 'u' (displacement, m) and cell data 'damage' (tensile, 0..1: the
    cell's volume-weighted mean; 0 in elastic cells) and 'unit'
    (1-based)."""
    a = specimen.assembly
    nb = int(np.count_nonzero(a.block_of_node >= 0))
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
    (1-based), 'area', 'axis' (of the joint's normal) and 'crack' (1 on a
    unit's crack interface, 0 on a mortar joint)."""
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
    joint, axis, crack = np.zeros(n, int), np.zeros(n, int), np.zeros(n, int)
    for c, jn in zip(a.contacts, specimen.contact_joint):
        joint[c.sc], axis[c.sc] = jn + 1, c.axis
        crack[c.sc] = specimen.joints[jn][0] == "crack"
    poly.point_data["u"] = disp
    poly.point_data["joint"] = joint
    poly.point_data["area"] = j.area
    poly.point_data["axis"] = axis
    poly.point_data["crack"] = crack
    poly.point_data["damage"] = state.joints.state[:, JS_D]
    return poly


def state_blocks(specimen, state):
    """The final state, readable by ParaView and pyvista: MultiBlock
    {zones, joints} in the initial geometry with the displacement 'u' as
    point data (ParaView: Warp By Vector)."""
    return pv.MultiBlock({"zones": zones_grid(specimen, state),
                          "joints": joints_points(specimen, state)})
