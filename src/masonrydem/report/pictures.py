"""Pictures of a run's 3-D state (specimen/state.py) with pyvista/VTK, off screen.

Off-screen rendering uses VTK's EGL window with Mesa (no X server needed):
VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow, pyvista.OFF_SCREEN = True.
"""
import os

import numpy as np
from matplotlib.colors import LinearSegmentedColormap

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import pyvista as pv  # noqa: E402

from ..analysis.plots import mark  # noqa: E402
from ..specimen.state import zones_grid  # noqa: E402

pv.OFF_SCREEN = True


def _camera(p, back=False):
    """Front (y = 0, load side) or back (y = t, the tension face in
    bending) view, slightly from above."""
    eye = (0.9, 1.7, 0.9) if back else (0.2, -1.6, 1.0)
    p.camera_position = [eye, (0.54, 0.057, 0.225), (0, 0, 1)]
    p.camera.zoom(1.25)


# the pictures' smallest text, in the window's pixels (VTK's font size):
# the report shows a picture scaled to its width, 1200 pixels to about a
# thousand at 1280 x 800, and text of this size reads at 9 pixels or more
TEXT = 18
# the bars' titles: pixels from the picture's foot, above the bars' tick labels
BAR_TITLE = 100


def _wrapped(text, window):
    """``text``'s lines wrapped to the window's width at TEXT (a
    character at most 0.7 of the font size wide)."""
    import textwrap
    width = int(0.95 * window[0] / (0.7 * TEXT))
    return "\n".join(w for line in text.split("\n") for w in textwrap.wrap(line, width) or [""])


def picture_numbering(specimen, path, window=(1600, 1000)):
    """The model with its units (U1..) and mortar joints (J1..) numbered;
    a unit's crack interface, where the model has them, is numbered after
    the mortar joints in the units' order (said in the title, not drawn:
    its label would sit on the unit's)."""
    a = specimen.assembly
    p = pv.Plotter(off_screen=True, window_size=window)
    grid = zones_grid(specimen)
    p.add_mesh(grid, scalars="unit", cmap="tab20", show_scalar_bar=False)
    pos_u = np.zeros((len(specimen.units), 3))
    vol = np.zeros(len(specimen.units))
    for blk in a.blocks:
        u = specimen.block_unit[blk.id]
        v = float(np.prod(np.asarray(blk.hi) - np.asarray(blk.lo)))
        pos_u[u] += v * (np.asarray(blk.lo) + np.asarray(blk.hi)) / 2
        vol[u] += v
    pos_u /= vol[:, None]
    pos_u[:, 1] = -0.002
    p.add_point_labels(pos_u, [f"U{u + 1}" for u in range(len(specimen.units))], font_size=TEXT + 2, point_size=1,
                       shape_color="white", always_visible=True)
    mortar = [jn for jn, (kind, _) in enumerate(specimen.joints) if kind != "crack"]
    pos_j = np.zeros((len(specimen.joints), 3))
    area = np.zeros(len(specimen.joints))
    for c, jn in zip(a.contacts, specimen.contact_joint):
        ba, bb = a.blocks[c.block_a], a.blocks[c.block_b]
        lo, hi = np.maximum(ba.lo, bb.lo), np.minimum(ba.hi, bb.hi)
        pos_j[jn] += c.area * (lo + hi) / 2
        area[jn] += c.area
    pos_j = pos_j[mortar] / area[mortar, None]
    pos_j[:, 1] = -0.004
    p.add_point_labels(pos_j, [f"J{j + 1}" for j in mortar], font_size=TEXT, point_size=6, point_color="red",
                       text_color="darkred", shape_opacity=0.75, always_visible=True)
    cracks = len(specimen.joints) - len(mortar)
    note = f"; the crack interface of unit Uk is J{len(mortar)}+k" if cracks else ""
    p.add_text(_wrapped(f"{specimen.scene.name}: {len(specimen.units)} units (U), {len(mortar)} mortar joints "
                        f"(J){note}", window), font_size=TEXT)
    _camera(p)
    p.screenshot(str(path))
    p.close()
    mark(path, TEXT)


# the units' cracking (cell damage, crack interfaces) in reds, the mortar
# joints' damage in blues: brick and joint failure told apart at a glance
UNIT_CMAP = LinearSegmentedColormap.from_list("unit cracking", ["#cdbfa6", "#e34a33", "#67000d"])
JOINT_CMAP = LinearSegmentedColormap.from_list("joint damage", ["#c6dbef", "#2171b5", "#08306b"])
SHOWN = 0.05        # a band's position whose largest damage is smaller is not drawn


def _bands(joints, magnify, crack, thickness, width=0.012):
    """The damage of the mortar joints (crack 0) or the units' crack
    interfaces (1) as bands on the back (tension) face, where a crack shows:
    along each joint, at each of its sub-contacts' positions, the largest D
    through the thickness (shown from SHOWN), on a band ``width`` (m) wide
    across the joint, at the displaced back face; cell data 'damage'."""
    pd_ = joints.point_data
    axis = pd_["axis"]
    keep = (pd_["crack"] == crack) & (axis != 1)
    x0, u, d, area = joints.points[keep], pd_["u"][keep], pd_["damage"][keep], pd_["area"][keep]
    along = np.where(axis[keep] == 0, 2, 0)             # a head joint runs up the face, a bed joint along it
    key = np.stack([pd_["joint"][keep], along, np.round(x0[np.arange(len(x0)), along], 5)], axis=1)
    _, group = np.unique(key, axis=0, return_inverse=True)
    group = group.ravel()
    n = group.max() + 1 if group.size else 0
    D = np.zeros(n)
    np.maximum.at(D, group, d)
    length = np.bincount(group, area, n) / thickness
    order = np.lexsort((x0[:, 1], group))               # by group, then towards the back face
    back = order[np.r_[np.flatnonzero(np.diff(group[order])), len(order) - 1]] if n else order
    shown = D >= SHOWN
    c = (x0 + magnify * u)[back[shown]] + [0.0, 0.003, 0.0]
    ax = along[back[shown]]
    e1, e2 = np.zeros((shown.sum(), 3)), np.zeros((shown.sum(), 3))
    e1[np.arange(len(ax)), ax] = 0.5 * length[shown]
    e2[np.arange(len(ax)), 2 - ax] = 0.5 * width
    corners = np.stack([c - e1 - e2, c + e1 - e2, c + e1 + e2, c - e1 + e2], axis=1).reshape(-1, 3)
    faces = np.hstack([np.full((len(c), 1), 4), np.arange(4 * len(c)).reshape(-1, 4)]).ravel()
    bands = pv.PolyData(corners, faces)
    bands.cell_data["damage"] = D[shown]
    return bands


def picture_damage(state, path, title="", magnify=None, window=(1600, 1000), rig=None):
    """The cracked, deformed state (a MultiBlock from ``state_blocks`` or
    read from state.vtm), seen from the back (tension) face: the units as
    solids with their edges, coloured by tensile damage (cells with damage
    >= 0.5 darkest); the cracks as bands (``_bands``) on the back face, the
    units' crack interfaces in the units' reds and the mortar joints in
    blues; displacements magnified (by default so that the largest is 3 %
    of the wall length), so that an open joint shows as a gap; ``rig`` (the
    scene's loading.bending) adds its supports (back face) and load lines
    (front face) as lines past the wall's top and bottom.  Returns the
    magnification."""
    zones, joints = state["zones"], state["joints"]
    if magnify is None:
        umax = float(np.abs(zones.point_data["u"]).max())
        magnify = 0.03 * float(np.ptp(zones.points[:, 0])) / umax if umax > 0 else 1.0
    zones = zones.warp_by_vector("u", factor=magnify)
    p = pv.Plotter(off_screen=True, window_size=window)
    # the bars at the foot, their tick labels above them and each bar's title above those, as a text of
    # its own (VTK's title of a bar would sit on the labels); the bars' own titles blank, told apart
    bar = dict(vertical=False, position_y=0.02, width=0.36, height=0.12, title_font_size=1,
               label_font_size=TEXT, n_labels=6, fmt="%.1f")
    p.add_mesh(zones, scalars="damage", cmap=UNIT_CMAP, clim=(0, 1), scalar_bar_args=dict(title=" ", position_x=0.06,
                                                                                          **bar))
    p.add_text("unit cracking: cell damage, crack interface D", position=(int(0.06 * window[0]), BAR_TITLE),
               font_size=TEXT // 2)         # pyvista doubles a placed text's size
    edges = zones.extract_surface(algorithm="dataset_surface").extract_feature_edges(
        boundary_edges=False, non_manifold_edges=False, manifold_edges=False, feature_angle=30)
    p.add_mesh(edges, color="#5a5a5a", line_width=1)
    cracked = zones.threshold(0.5, scalars="damage")
    if cracked.n_cells:
        p.add_mesh(cracked, color=UNIT_CMAP(1.0)[:3], show_scalar_bar=False)
    thickness = float(np.ptp(state["zones"].points[:, 1]))
    for crack, cmap in ((1, UNIT_CMAP), (0, JOINT_CMAP)):
        bands = _bands(joints, magnify, crack, thickness)
        if bands.n_cells:
            p.add_mesh(bands, scalars="damage", cmap=cmap, clim=(0, 1), show_scalar_bar=not crack, lighting=False,
                       scalar_bar_args=dict(title="  ", position_x=0.56, **bar))
            if not crack:
                p.add_text("mortar joint damage D", position=(int(0.56 * window[0]), BAR_TITLE), font_size=TEXT // 2)
    if rig is not None:
        (_, _, y0, y1, z0, z1) = state["zones"].bounds
        (x0, x1, _, _, _, _) = state["zones"].bounds
        for xs, y, color in ((rig.supports, y1, "black"), (rig.loads, y0, "darkgreen")):
            for x in xs:
                ends = (((x0 - 0.04, y, x), (x1 + 0.04, y, x)) if rig.direction == "vertical"
                        else ((x, y, z0 - 0.04), (x, y, z1 + 0.04)))
                p.add_mesh(pv.Line(*ends).tube(radius=0.004), color=color)
    p.add_text(_wrapped(f"{title}\nback (tension) face, displacements x {magnify:.0f}; bands: a joint's largest "
                        f"damage through the thickness (from {SHOWN:g}); unit cells with damage >= 0.5 darkest"
                        + ("\nlines: supports black (back face), loads green (front face)" if rig is not None else ""),
                        window), font_size=TEXT)
    _camera(p, back=True)
    p.screenshot(str(path))
    p.close()
    mark(path, TEXT)
    return magnify
