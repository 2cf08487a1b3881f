"""Masonry rules shared by the scenes, the study and its analysis: the
modelled unit, the running bond, the joint stiffness from the unit's
modulus, the fracture-energy rules and the flexural strength.

These are the rules of the study's description (docs/study.md, 3),
written once here so that the specimen builder, the sampled scenes and the
regression all use the same numbers.
"""
import numpy as np

# G_I (N/m) per f_tj (Pa): 0.03 N/mm per MPa
GI_PER_FT = 0.03 * 1e3 / 1e6
# G_fu = 0.04 f_tu^0.7 (N/mm with f_tu in MPa)
GF_COEFFICIENT, GF_EXPONENT = 0.04, 0.7


def unit_fracture_energy(f_tu, coefficient=GF_COEFFICIENT, exponent=GF_EXPONENT):
    """G_fu = coefficient f_tu^exponent (N/mm, f in MPa), returned in N/m
    for f_tu in Pa."""
    return 1e3 * coefficient * (np.asarray(f_tu, float) / 1e6) ** exponent


def joint_kn(E_b, Em_ratio, t):
    """Normal stiffness of a zero-thickness joint standing for a mortar
    layer of thickness t between units of modulus E_b:
    k_n = E_b E_m / (t (E_b - E_m)), E_m = Em_ratio E_b."""
    E_m = Em_ratio * E_b
    return E_b * E_m / (t * (E_b - E_m))


def modelled_unit(geometry):
    """Modelled unit (brick + half a joint on each side in length and
    height; no joint through the thickness): (length, width, height)."""
    u, t = geometry["unit"], geometry["joint_thickness"]
    return u["length"] + t, u["width"], u["height"] + t


def bond_overlap(geometry):
    """l_o: the overlap of units in successive courses (bond offset x the
    modelled unit's length)."""
    return geometry["bond_offset"] * modelled_unit(geometry)[0]


def course_span(geometry, k):
    """x-range of course k (odd courses shifted by the bond offset)."""
    L = modelled_unit(geometry)[0]
    x0 = geometry["bond_offset"] * L if k % 2 else 0.0
    return x0, x0 + geometry["units_per_course"] * L


def wall_length(geometry):
    """Overall length of the running-bond wall (the courses together)."""
    L = modelled_unit(geometry)[0]
    return L * (geometry["units_per_course"] + (geometry["bond_offset"] if geometry["courses"] > 1 else 0))


def crack_band_error(geometry, cells_along):
    """Why a unit mesh with ``cells_along`` cells along the unit's length
    cannot carry a crack through the unit where it runs, or None.

    In running bond a line crack through a unit follows the plane in line
    with the head joints of the courses above and below: at the bond
    offset b L from the unit's end.  The crack band (the zones that soften)
    must be able to sit on that plane: a cell must be centred on it,
    b n - 1/2 an integer for n cells (for b = 1/2: n odd).  When a node
    plane lies there instead (n even for b = 1/2), the band has to sit
    beside it and jog by half a cell at every bed joint, and the capacity
    converges slowly from above (measured: 7 and 9 cells against 8)."""
    b = geometry["bond_offset"]
    if geometry["courses"] < 2 or b <= 0.0 or b >= 1.0:
        return None
    k = b * cells_along - 0.5
    if abs(k - round(k)) < 1e-9:
        return None
    need = "an odd number" if abs(b - 0.5) < 1e-12 else f"n with {b:g} n - 1/2 an integer"
    return (f"a unit's crack plane (in line with the head joints of the next courses, {b:g} of its length from "
            f"its end) must fall in the middle of a cell, not on a node plane: use {need} of cells along the unit, "
            f"got {cells_along}")


def crack_plane(geometry, k):
    """Where a line crack crosses a unit of course k: the distance from its
    left end of the plane in line with the head joints of the courses
    above and below (b L in courses shifted by the bond offset b L against
    the course below, (1 - b) L in the others; L / 2 for half bond, and in
    stack bond, where no head joint crosses a unit)."""
    L = modelled_unit(geometry)[0]
    b = geometry["bond_offset"]
    if not 0.0 < b < 1.0:       # stack bond: the head joints line up; a unit cracks at mid-length
        return 0.5 * L
    return (1.0 - b) * L if k % 2 else b * L


def running_bond_joints(courses, per_course):
    """Joints numbered as contact planes: the head joints course by course
    (per_course - 1 per course), then one bed-joint plane under each unit
    of courses 1.. (a plane may touch one or two units below).  Returns a
    list of (kind, unit) with unit = (course, index) of the unit to the
    left of a head joint or above a bed plane."""
    head = [("head", (k, i)) for k in range(courses) for i in range(per_course - 1)]
    bed = [("bed", (k, i)) for k in range(1, courses) for i in range(per_course)]
    return head + bed


def flexural_strength(P, shear_span, section_height, thickness):
    """Four-point bending: sigma = 6 M / (b h^2), M = P/2 a (P the total
    load, a the shear span, b the section height, h the thickness)."""
    return 6.0 * (0.5 * shear_span * P) / (section_height * thickness * thickness)
