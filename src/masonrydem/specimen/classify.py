"""Failure classification of a wallette run (docs/formulation.md, 11), automatic and
explained.

A cell (hexahedron of a unit) is cracked when the volume-weighted mean
tensile damage of its 10 zones reaches ``crack_damage``.  A unit is cracked
through when, along one of its axes, a layer of cells is at least
``crack_through`` cracked (a crack across the unit); a potential-crack unit
when that share of its crack interface's area is past its strength.  The run is a "brick"
failure when at least one unit is cracked through, otherwise a "joint"
failure (separation and/or sliding of joints).  A joint (contact plane) is
broken when its area-weighted mean damage reaches ``broken_joint_damage``.
"""
import numpy as np

from ..dem import JS_D, zone_damage


def _zone_blocks(assembly):
    """(block number, block) of the blocks meshed into zones."""
    return [(b, blk) for b, blk in enumerate(assembly.blocks) if blk.element == "zones"]


def cell_damage(specimen, state):
    """Per zone block: array (nx, ny, nz) of cell damage (volume-weighted
    mean tensile damage of the cell's 10 tetrahedra) and the cell volumes;
    none for rigid units (they cannot crack)."""
    a = specimen.assembly
    if a.rigid:
        return []
    z = state.zones
    d = zone_damage(state)
    wv = z.vol * z.wt
    out = []
    for b, blk in _zone_blocks(a):
        s, e = a.zone_ptr[b], a.zone_ptr[b + 1]
        nx, ny, nz = blk.cells
        w = wv[s:e].reshape(-1, 10)
        dc = (d[s:e].reshape(-1, 10) * w).sum(axis=1) / w.sum(axis=1)
        out.append((dc.reshape((nx, ny, nz), order="F"), w.sum(axis=1).reshape((nx, ny, nz), order="F")))
    return out


def joint_damage(specimen, state):
    """Area-weighted mean damage D of each joint (contact plane)."""
    area = state.joints.area
    D = state.joints.state[:, JS_D]
    num = np.zeros(len(specimen.joints))
    den = np.zeros(len(specimen.joints))
    for c, j in zip(specimen.assembly.contacts, specimen.contact_joint):
        num[j] += np.sum(D[c.sc] * area[c.sc])
        den[j] += np.sum(area[c.sc])
    return num / np.where(den > 0, den, 1.0)


def crack_fractions(specimen, state, crack_damage):
    """Per unit, the largest cracked share of a section through it, and the
    cracked and total measure (volume of zones, or area of crack
    interfaces).  Elasto-plastic units: the cracked share of a layer of
    cells across one of its axes, a cell cracked when its mean damage
    reaches ``crack_damage``; potential-crack units: the area share of its
    crack interface past its strength (D > 0): the interface, unlike a
    cell, has no width to average its process zone over (measured at the
    load-drop stop of a brick failure: 66 % of the interface past its
    strength, 47 % at D >= 0.5; of a joint failure at most 1 %); rigid and
    elastic units cannot crack."""
    n = len(specimen.units)
    fractions = np.zeros(n)
    if specimen.assembly.rigid:
        return fractions, 0.0, 0.0
    if ("crack", specimen.units[0]) in specimen.joints:
        area, D = state.joints.area, state.joints.state[:, JS_D]
        cracked, total = np.zeros(n), np.zeros(n)
        for c, j in zip(specimen.assembly.contacts, specimen.contact_joint):
            kind, unit = specimen.joints[j]
            if kind == "crack":
                u = specimen.units.index(unit)
                cracked[u] += np.sum(area[c.sc][D[c.sc] > 0.0])
                total[u] += np.sum(area[c.sc])
        return cracked / total, float(cracked.sum()), float(total.sum())
    cracked_vol = total_vol = 0.0
    for (_, blk), (dc, vol) in zip(_zone_blocks(specimen.assembly), cell_damage(specimen, state)):
        cracked = dc >= crack_damage
        cracked_vol += vol[cracked].sum()
        total_vol += vol.sum()
        layer = max(cracked.mean(axis=tuple(a for a in range(3) if a != ax)).max() for ax in range(3))
        u = specimen.block_unit[blk.id]
        fractions[u] = max(fractions[u], float(layer))
    return fractions, cracked_vol, total_vol


def bed_planes(specimen, state):
    """Per bed-joint plane (between courses k - 1 and k, k = 1..), the
    area-weighted mean damage of its joints: {k: D}.  In vertical bending
    the wallette fails along the plane with the largest."""
    area = state.joints.area
    D = state.joints.state[:, JS_D]
    num, den = {}, {}
    for c, j in zip(specimen.assembly.contacts, specimen.contact_joint):
        kind, (k, _) = specimen.joints[j]
        if kind == "bed":
            num[k] = num.get(k, 0.0) + float(np.sum(D[c.sc] * area[c.sc]))
            den[k] = den.get(k, 0.0) + float(np.sum(area[c.sc]))
    return {k: num[k] / den[k] for k in sorted(num)}


def classify(specimen, state, crack_damage=0.5, crack_through=0.5, broken_joint_damage=0.5):
    """Returns a dict: failure_mode ('brick' or 'joint'), the evidence
    columns and a one-line explanation."""
    fractions, cracked, total = crack_fractions(specimen, state, crack_damage)
    through = np.flatnonzero(fractions >= crack_through)
    mortar = np.array([kind != "crack" for kind, _ in specimen.joints])
    jd = joint_damage(specimen, state)[mortar]
    broken = np.flatnonzero(jd >= broken_joint_damage)
    mode = "brick" if through.size else "joint"
    what = "its crack interface" if not mortar.all() else "a layer of cells"
    if specimen.assembly.rigid:
        why = "joint failure: the units are rigid (they cannot crack)"
    elif through.size:
        why = (f"brick failure: unit(s) {', '.join(str(u + 1) for u in through)} cracked through "
               f"({what} at least {crack_through:.0%} cracked; largest {fractions.max():.0%})")
    else:
        why = (f"joint failure: no unit cracked through (largest cracked share of {what} "
               f"{fractions.max():.0%} < {crack_through:.0%})")
    why += f"; {broken.size} of {jd.size} joints broken (mean damage >= {broken_joint_damage})"
    bend = specimen.scene.loading
    if bend.test == "bending" and bend.bending.direction == "vertical" and mode == "joint":
        planes = bed_planes(specimen, state)
        k = max(planes, key=planes.get)
        why += (f"; the crack runs along the bed joint between courses {k} and {k + 1} (its mean damage "
                f"{planes[k]:.2f}, the next plane's {sorted(planes.values())[-2]:.2f})")
    return dict(
        failure_mode=mode,
        cracked_units=int(through.size),
        unit_crack_fraction=float(fractions.max()) if fractions.size else 0.0,
        cracked_brick_volume_frac=float(cracked / total) if total else 0.0,
        broken_joints=int(broken.size),
        n_joints=int(jd.size),
        classification=why,
    )
