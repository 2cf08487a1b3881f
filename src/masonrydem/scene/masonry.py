"""Masonry rules shared by the scenes, the study and its analysis, each
written once: the running-bond wall (``Geometry``), the dependent
material properties (``unit_fields``, ``joint_fields``), the joint
stiffness from the units' modulus and the flexural strength
(docs/study.md, 1-3).  The rules' coefficients are the scene's (a study
file sets them as its rules).

A property given once for the wall and one given per unit or joint go
through the same rules: the former is a field with one value everywhere.
"""
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Geometry:
    """A running-bond wall of ``courses`` x ``units_per_course`` units
    (brick sizes without mortar, m); every second course shifted by
    ``bond_offset`` of the modelled unit's length.  The modelled unit is the
    brick plus half a joint on each side in length and height (simplified
    micro-model; no joint through the thickness)."""
    unit_length: float
    unit_height: float
    unit_width: float
    joint_thickness: float
    courses: int
    units_per_course: int
    bond_offset: float
    ends: str = "toothed"       # or straight: the shifted courses end in cut units

    @property
    def modelled_unit(self):
        """(length, width, height) of the modelled unit."""
        t = self.joint_thickness
        return self.unit_length + t, self.unit_width, self.unit_height + t

    @property
    def n_units(self):
        """(In closed form: a scene's size is checked before anything
        the size of the wall is made.)"""
        return self.courses * self.units_per_course + int(self._cut(1)) * (self.courses // 2)

    def units_in_course(self, k):
        """How many units course k has: units_per_course, and one more
        (two cut ones for one whole) in a shifted course with straight ends."""
        return self.units_per_course + int(self._cut(k))

    def _cut(self, k):
        return self.ends == "straight" and k % 2 == 1 and 0.0 < self.bond_offset < 1.0

    def unit_spans(self, k):
        """(x0, x1) of each unit of course k, left to right."""
        L, n = self.modelled_unit[0], self.units_per_course
        x0 = self.course_span(k)[0]
        if not self._cut(k):
            return [(x0 + i * L, x0 + (i + 1) * L) for i in range(n)]
        b = self.bond_offset * L
        return [(0.0, b)] + [(b + i * L, b + (i + 1) * L) for i in range(n - 1)] + [(b + (n - 1) * L, n * L)]

    @property
    def joints(self):
        """The joints as contact planes (``running_bond_joints``)."""
        return running_bond_joints([self.units_in_course(k) for k in range(self.courses)])

    @property
    def bond_overlap(self):
        """l_o: the overlap of units in successive courses."""
        return self.bond_offset * self.modelled_unit[0]

    @property
    def height(self):
        return self.courses * self.modelled_unit[2]

    @property
    def built_height(self):
        """The wall's height as built: its courses and the bed joints between
        them (the modelled units' half joints at the top and the bottom are
        not masonry): the section height b of the bending test."""
        return self.courses * self.unit_height + (self.courses - 1) * self.joint_thickness

    @property
    def bed_length(self):
        """The length as built over which every course's bed joints bear
        (where all courses overlap, less the half joints at its ends, which
        are not masonry): the section width b of vertical bending."""
        x0, x1 = self.common_span
        return x1 - x0 - self.joint_thickness

    @property
    def common_span(self):
        """(x0, x1): the stretch every course covers."""
        spans = [self.course_span(k) for k in range(min(self.courses, 2))]
        return max(s[0] for s in spans), min(s[1] for s in spans)

    @property
    def length(self):
        """Overall length of the wall (the courses together)."""
        shifted = self.courses > 1 and self.ends == "toothed"
        return self.modelled_unit[0] * (self.units_per_course + (self.bond_offset if shifted else 0))

    def item_centres(self):
        """Where each unit and each joint sits on the wall's face: per 'unit'
        and 'joint' an array of (x, z) in m, in the order of the per-unit
        and per-joint properties (units course by course; joints as
        ``joints`` numbers them: a head joint at its plane, a bed plane at
        the middle of the unit above it)."""
        L, _, H = self.modelled_unit
        units, ends = {}, {}     # a unit's centre and its right end
        for k in range(self.courses):
            for i, (x0, x1) in enumerate(self.unit_spans(k)):
                whole = not self._cut(k)
                units[(k, i)] = (self.course_span(k)[0] + (i + 0.5) * L if whole else 0.5 * (x0 + x1),
                                 (k + 0.5) * H)
                ends[(k, i)] = units[(k, i)][0] + 0.5 * L if whole else x1
        joints = [(ends[u], units[u][1]) if kind == "head" else (units[u][0], u[0] * H)
                  for kind, u in self.joints]
        return {"unit": np.array(list(units.values())), "joint": np.array(joints).reshape(-1, 2)}

    def course_span(self, k):
        """x-range of course k (odd courses shifted by the bond offset, with
        toothed ends)."""
        L = self.modelled_unit[0]
        x0 = self.bond_offset * L if k % 2 and self.ends == "toothed" else 0.0
        return x0, x0 + self.units_per_course * L

    def crack_plane(self, k):
        """Where a line crack crosses a unit of course k: the distance from
        its left end of the plane in line with the head joints of the
        courses above and below (b L in courses shifted by the bond offset
        b L against the course below, (1 - b) L in the others; L / 2 for
        half bond, and in stack bond, where no head joint crosses a unit)."""
        L = self.modelled_unit[0]
        b = self.bond_offset
        if not 0.0 < b < 1.0:       # stack bond: the head joints line up; a unit cracks at mid-length
            return 0.5 * L
        return (1.0 - b) * L if k % 2 else b * L

    def crack_band_error(self, cells_along):
        """Why a unit mesh with ``cells_along`` cells along the unit's
        length cannot carry a crack through the unit where it runs, or None.

        In running bond a line crack through a unit follows the plane in
        line with the head joints of the courses above and below: at the
        bond offset b L from the unit's end.  The crack band (the zones
        that soften) must be able to sit on that plane: a cell must be
        centred on it, b n - 1/2 an integer for n cells (for b = 1/2: n
        odd).  When a node plane lies there instead, the band has to sit
        beside it and jog by half a cell at every bed joint, and the
        capacity converges slowly from above (docs/accuracy.md)."""
        b = self.bond_offset
        if self.courses < 2 or b <= 0.0 or b >= 1.0:
            return None
        k = b * cells_along - 0.5
        if abs(k - round(k)) < 1e-9:
            return None
        need = "an odd number" if abs(b - 0.5) < 1e-12 else f"n with {b:g} n - 1/2 an integer"
        return (f"a unit's crack plane (in line with the head joints of the next courses, {b:g} of its length "
                f"from its end) must fall in the middle of a cell, not on a node plane: use {need} of cells "
                f"along the unit, got {cells_along}")


def running_bond_joints(counts):
    """Joints numbered as contact planes, for courses of ``counts`` units:
    the head joints course by course (count - 1 per course), then one
    bed-joint plane under each unit of courses 1.. (a plane may touch one
    or two units below).  Returns a list of (kind, unit) with unit =
    (course, index) of the unit to the left of a head joint or above a bed
    plane."""
    head = [("head", (k, i)) for k, n in enumerate(counts) for i in range(n - 1)]
    bed = [("bed", (k, i)) for k, n in enumerate(counts) if k for i in range(n)]
    return head + bed


def _frozen(values):
    a = np.array(values, float)
    a.flags.writeable = False
    return a


@dataclass(frozen=True)
class UnitFields:
    """The units' properties, one value per unit (read-only arrays):
    E (Pa), ft (Pa), c = c_ratio ft (Pa), Gf (N/m); and those the wall
    shares: nu, phi and psi (deg), density (kg/m^3), crack_kn_ratio."""
    E: np.ndarray
    ft: np.ndarray
    c: np.ndarray
    Gf: np.ndarray
    nu: float
    phi: float
    density: float
    crack_kn_ratio: float
    psi: float = 0.0


@dataclass(frozen=True)
class JointFields:
    """The mortar joints' properties, one value per joint (read-only
    arrays): ft, c = c_ratio ft (Pa), phi (deg), G_I and G_II = GII_ratio
    G_I (N/m); the rules' ratios (GII_ratio also serves the units' crack
    interfaces) and the stiffness rules the wall shares (``joint_kn``):
    Em_ratio, ks_ratio; residual_friction_ratio, tan(phi_r) / tan(phi)."""
    ft: np.ndarray
    c: np.ndarray
    phi: np.ndarray
    GI: np.ndarray
    GII: np.ndarray
    c_ratio: float
    Em_ratio: float
    ks_ratio: float
    GII_ratio: float
    residual_friction_ratio: float = 1.0


def unit_fields(E, ft, nu, c_ratio, phi, Gf, density, crack_kn_ratio, gf_rule=None, psi=0.0):
    """The units' fields from their E and ft (one value per unit) by the
    rules c_u = c_ratio f_tu and, with ``gf_rule`` = (coefficient,
    exponent), G_fu = coefficient f_tu^exponent (``unit_fracture_energy``);
    without it G_fu = ``Gf`` for every unit."""
    ft = _frozen(ft)
    if gf_rule is None:
        gf = np.full(ft.size, float(Gf))
    else:   # unit by unit: a scalar power, as every unit has always had it
        gf = [float(unit_fracture_energy(f, *gf_rule)) for f in ft]
    return UnitFields(E=_frozen(E), ft=ft, c=_frozen(c_ratio * ft), Gf=_frozen(gf), nu=float(nu), phi=float(phi),
                      density=float(density), crack_kn_ratio=float(crack_kn_ratio), psi=float(psi))


def joint_fields(ft, phi, c_ratio, GI, GII_ratio, Em_ratio, ks_ratio, gi_per_ft=None, residual_friction_ratio=1.0):
    """The joints' fields from their ft and phi (one value per joint) by
    the rules c_j = c_ratio f_tj, G_II = GII_ratio G_I and, with
    ``gi_per_ft``, G_I = gi_per_ft f_tj; without it G_I = ``GI``."""
    ft = _frozen(ft)
    gi = _frozen(gi_per_ft * ft if gi_per_ft is not None else np.full(ft.size, float(GI)))
    return JointFields(ft=ft, c=_frozen(c_ratio * ft), phi=_frozen(phi), GI=gi, GII=_frozen(GII_ratio * gi),
                       c_ratio=float(c_ratio), Em_ratio=float(Em_ratio), ks_ratio=float(ks_ratio), GII_ratio=float(GII_ratio),
                       residual_friction_ratio=float(residual_friction_ratio))


def unit_fracture_energy(f_tu, coefficient, exponent):
    """G_fu = coefficient f_tu^exponent (N/mm, f in MPa), returned in N/m
    for f_tu in Pa."""
    return 1e3 * coefficient * (np.asarray(f_tu, float) / 1e6) ** exponent


def joint_kn(E_b, Em_ratio, t):
    """Normal stiffness of a zero-thickness joint standing for a mortar
    layer of thickness t between units of modulus E_b:
    k_n = E_b E_m / (t (E_b - E_m)), E_m = Em_ratio E_b."""
    E_m = Em_ratio * E_b
    return E_b * E_m / (t * (E_b - E_m))


def joint_stiffness(E_a, E_b, joints, t):
    """(k_n, k_s) of a mortar joint between units of moduli E_a and E_b:
    ``joint_kn`` of their mean, k_s = ks_ratio k_n."""
    kn = joint_kn(0.5 * (E_a + E_b), joints.Em_ratio, t)
    return kn, joints.ks_ratio * kn


def crack_stiffness(E, L, units, joints):
    """(k_n, k_s) of a potential-crack unit's interface: crack_kn_ratio E / L
    (L the modelled unit's length), k_s = ks_ratio k_n."""
    kn = units.crack_kn_ratio * E / L
    return kn, joints.ks_ratio * kn


def flexural_strength(P, shear_span, section, thickness):
    """Four-point bending: sigma = 6 M / (b h^2), M = P/2 a (P the total
    load, a the shear span, b the section (horizontal bending: its
    height; vertical: its width), h the thickness)."""
    return 6.0 * (0.5 * shear_span * P) / (section * thickness * thickness)
