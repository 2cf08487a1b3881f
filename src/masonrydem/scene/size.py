"""The size of the model a scene builds, estimated from its numbers alone
(``model_size``), and the refusal of a model too large for the machine's
memory (``check_size``), before anything is allocated."""
import os
from dataclasses import replace

from ..errors import InputError


# bytes per item of a model at the peak of building it and setting up its
# solver, measured on the wallette and rounded up (9 x 4 x 3 cells: 25,920
# tetrahedra and 7,119 sub-contacts, 80 MB; rigid units at refine 4: 29,597
# sub-contacts, 34 MB; potential-crack hex8i 4 x 4 x 3, refine 2: 1,152
# cells and 14,637 sub-contacts, 17 MB)
ITEM_BYTES = dict(nodes=500, tetrahedra=3000, cells=5000, sub_contacts=1500)


def model_size(g, physics, disc, loading):
    """An upper estimate of the model a scene builds, from its numbers alone
    (nothing allocated): nodes, tetrahedra (zones), linear cells,
    sub-contacts (joints, crack interfaces and strips: composite Simpson
    points, 2 r + 1 per interval and direction at refine r) and bytes
    (ITEM_BYTES)."""
    model = physics.model
    units = g.n_units
    r = disc.refine
    pieces = 2 if model.crack_interface else 1
    a, b, c = max(disc.cells[0], pieces), disc.cells[1], disc.cells[2]

    def simpson(m, rm, n, rn):      # points on a face of m x n intervals, refined rm and rn times
        return (2 * rm * m + 1) * (2 * rn * n + 1)

    bend = loading.bending
    strips = len(bend.supports) + len(bend.loads) if loading.test == "bending" else 0
    # per unit a head joint (and its crack interface) and a bed joint on the
    # union of two face grids, offset by the bond (their lines coincide when
    # the offset falls on a grid line); strips across the wall's height, a
    # few cells wide.  Faces normal to x: (y, z); to z: (x, y); strips (normal to y): (z, x)
    shift = g.bond_offset * a
    along = a if abs(shift - round(shift)) < 1e-9 else 2 * a
    subs = (units * (simpson(b, r.head[1], c, r.head[2]) + (pieces - 1) * simpson(b, r.crack[1], c, r.crack[2])
                     + simpson(along, r.bed[0], b, r.bed[1]))
            + strips * (simpson(g.courses * c, r.strips[2], 3, r.strips[0]) if bend.axis == 0
                        else simpson(along * g.units_per_course, r.strips[0], 3, r.strips[2])))
    # a platen, and in vertical bending a base strip that turns: a node
    # each (and one more for a turn), and sub-contacts on the top or bottom
    # course's faces
    platen = bool(loading.precompression.platen and loading.precompression.pressure)
    base = int(loading.test == "bending" and bend.axis == 2)
    subs += (platen + base) * g.units_per_course * simpson(along, r.strips[0], b, r.strips[1])
    hexes = 0 if model.rigid else units * a * b * c
    zones = model.material != "elastic" or disc.elastic_element == "zones"
    turns = (strips if bend.strips_turn else 0) + base + (platen if base else 0) if not model.rigid else 0
    size = dict(nodes=strips + turns + platen + base
                + units * (pieces if model.rigid else (a + pieces) * (b + 1) * (c + 1)),
                tetrahedra=10 * hexes if zones else 0, cells=0 if zones else hexes, sub_contacts=subs)
    size["bytes"] = sum(ITEM_BYTES[k] * n for k, n in size.items())
    return size


def memory_bytes():
    """The machine's physical memory, or None if unknown."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None


def check_size(g, physics, disc, loading, defaults):
    """Refuses a model that would not fit in the machine's memory (it would
    end in a MemoryError after seconds or minutes of building), naming the
    setting to blame: the wall if it is too large at the schema's default
    cells and refinement, else the cells if too many at refinement 1, else
    the refinement (``defaults``: the discretization at the schema's
    defaults)."""
    memory = memory_bytes()
    size = model_size(g, physics, disc, loading)
    if memory is None or size["bytes"] <= memory:
        return
    def fits(num):
        return model_size(g, physics, num, loading)["bytes"] <= memory

    if not fits(replace(disc, cells=defaults.cells, refine=defaults.refine)):
        field = "geometry.courses" if g.courses >= g.units_per_course else "geometry.units_per_course"
    else:
        field = "numerics.subcontact_refine" if fits(replace(disc, refine=defaults.refine)) else "numerics.cells"
    raise InputError(field, f"the model would need an estimated {_big(size['bytes'], 1e9)} GB of memory, more "
                     f"than this machine's {memory / 1e9:.3g} GB: {_big(size['tetrahedra'])} tetrahedra, "
                     f"{_big(size['cells'])} linear cells and {_big(size['sub_contacts'])} sub-contacts for "
                     f"{_big(g.n_units)} units (geometry.courses {g.courses} x geometry.units_per_course "
                     f"{g.units_per_course}) at disc.cells {list(disc.cells)} and "
                     f"numerics.subcontact_refine {disc.refine_label}; use fewer cells, a lower refinement or "
                     "a smaller wall")


def _big(n, unit=1):
    return f"{n / unit:.3g}" if n < 10 ** 300 else f"over {1e300 / unit:.3g}"
