"""Constitutive laws, Python side: the tables of laws, validated
parameters -> kernel rows.

The laws themselves are small jitted functions in ``kernels.zones`` and
``kernels.joint_laws``.  Each joint law is declared once, in
``JOINT_LAWS``: its name (a scene's ``physics.joints``; the scene schema
lists the same names, a test checks it), its kernel id and the parameters it reads, which are validated
(refusing bad values with the field's name) and packed into the
per-zone / per-sub-contact rows the kernels read.
"""
import math
from dataclasses import dataclass, fields

import numpy as np

from . import kernels as K
from ..errors import InputError


def _number(value):
    return isinstance(value, (int, float, np.floating, np.integer)) and math.isfinite(value)


def _positive(field, value):
    if not (_number(value) and value > 0):
        raise InputError(field, f"must be a positive number, got {value!r}")
    return float(value)


def _non_negative(field, value):
    if not (_number(value) and value >= 0):
        raise InputError(field, f"must be a non-negative number, got {value!r}")
    return float(value)


def _angle(field, value):
    if not (_number(value) and 0.0 <= value < 90.0):
        raise InputError(field, f"must be an angle in degrees in [0, 90), got {value!r}")
    return float(value)


# --- block materials ---------------------------------------------------------
@dataclass(frozen=True)
class Elastic:
    """Isotropic linear elastic block material: Young's modulus E (Pa),
    Poisson's ratio nu; density (kg/m^3) for dynamics and gravity."""
    E: float
    nu: float
    density: float = 0.0
    law_id = K.ZONE_ELASTIC

    def validate(self, where):
        _positive(f"{where}.E", self.E)
        if not (_number(self.nu) and -1.0 < self.nu < 0.5):
            raise InputError(f"{where}.nu", f"Poisson's ratio must be in (-1, 0.5), got {self.nu!r}")
        _non_negative(f"{where}.density", self.density)

    @classmethod
    def of(cls, **props):
        """The material from a unit's properties (those it has no field for,
        strengths for an elastic one, are ignored)."""
        return cls(**{f.name: props[f.name] for f in fields(cls)})

    def moduli(self):
        """Bulk and shear moduli K = E / (3(1-2nu)), G = E / (2(1+nu))."""
        return self.E / (3.0 * (1.0 - 2.0 * self.nu)), self.E / (2.0 * (1.0 + self.nu))

    def row(self):
        """Kernel row; infinite strengths, so that an elastic block is also
        a valid (never yielding) row for the Mohr-Coulomb kernel."""
        k, g = self.moduli()
        r = np.zeros(K.N_ZP)
        r[K.ZP_K], r[K.ZP_G] = k, g
        r[K.ZP_FT] = r[K.ZP_C] = np.inf
        r[K.ZP_NPHI] = 1.0
        return r


@dataclass(frozen=True)
class MohrCoulomb(Elastic):
    """Elasto-plastic Mohr-Coulomb with tension cut-off and linear tension
    softening regularised by the crack band (kernels.zones.zone_mohr_coulomb).
    ft tensile strength (Pa), c cohesion (Pa), phi friction angle (deg),
    Gf mode-I fracture energy (N/m).  Shear: perfectly plastic, zero
    dilation."""
    ft: float = 0.0
    c: float = 0.0
    phi: float = 0.0
    Gf: float = 0.0
    law_id = K.ZONE_MOHR_COULOMB

    def validate(self, where):
        super().validate(where)
        _positive(f"{where}.ft", self.ft)
        _positive(f"{where}.c", self.c)
        _angle(f"{where}.phi", self.phi)
        _positive(f"{where}.Gf", self.Gf)

    def row(self):
        r = super().row()
        s = math.sin(math.radians(self.phi))
        nphi = (1.0 + s) / (1.0 - s)
        # FLAC: the tensile strength may not exceed the apex c / tan(phi)
        ft = self.ft if self.phi == 0 else min(self.ft, self.c / math.tan(math.radians(self.phi)))
        r[K.ZP_FT], r[K.ZP_C], r[K.ZP_NPHI], r[K.ZP_GF] = ft, self.c, nphi, self.Gf
        return r


# --- joint laws --------------------------------------------------------------
@dataclass(frozen=True)
class JointLaw:
    """A joint law: its name in a scene (``physics.joints``), its kernel id
    and the JointProps fields it reads (each validated by FIELD_RULES)."""
    name: str
    id: int
    fields: tuple


JOINT_LAWS = {law.name: law for law in (
    JointLaw("elastic", K.JOINT_ELASTIC, ("kn", "ks")),
    JointLaw("brittle_coulomb", K.JOINT_BRITTLE_COULOMB, ("kn", "ks", "ft", "c", "phi")),
    JointLaw("coupled_softening", K.JOINT_COUPLED, ("kn", "ks", "ft", "c", "phi", "GI", "GII")),
    JointLaw("friction", K.JOINT_FRICTION, ("kn", "ks", "phi")),
    # variants of coupled_softening for the model-form study (kernels.joint_laws._softened)
    JointLaw("coupled_exponential", K.JOINT_COUPLED_EXPONENTIAL, ("kn", "ks", "ft", "c", "phi", "GI", "GII")),
    JointLaw("coupled_lourenco_rots", K.JOINT_COUPLED_ADDITIVE, ("kn", "ks", "ft", "c", "phi", "GI", "GII")),
    JointLaw("coupled_friction_slip", K.JOINT_COUPLED_FRICTION_SLIP, ("kn", "ks", "ft", "c", "phi", "GI", "GII")),
    JointLaw("coupled_total_slip", K.JOINT_COUPLED_TOTAL_SLIP, ("kn", "ks", "ft", "c", "phi", "GI", "GII")),
)}

# a field's rule: (props, field name) -> None or InputError; a joint with
# strength needs a positive fracture energy to soften
FIELD_RULES = {
    "kn": lambda p, f: _positive(f, p.kn),
    "ks": lambda p, f: _positive(f, p.ks),
    "ft": lambda p, f: _non_negative(f, p.ft),
    "c": lambda p, f: _non_negative(f, p.c),
    "phi": lambda p, f: _angle(f, p.phi),
    "GI": lambda p, f: p.ft > 0 and _positive(f, p.GI),
    "GII": lambda p, f: p.c > 0 and _positive(f, p.GII),
    "residual": lambda p, f: _fraction(f, p.residual),
    "psi": lambda p, f: _angle(f, p.psi),
}


def _fraction(field, value):
    if not (_number(value) and 0.0 < value <= 1.0):
        raise InputError(field, f"must be in (0, 1], got {value!r}")
    return float(value)


def joint_law(name, field="joints.law"):
    """The law named ``name`` (JOINT_LAWS), or InputError naming ``field``."""
    try:
        return JOINT_LAWS[name]
    except (KeyError, TypeError):
        raise InputError(field, f"unknown joint law {name!r}; known: "
                         f"{', '.join(sorted(JOINT_LAWS))}") from None


@dataclass(frozen=True)
class JointProps:
    """Zero-thickness joint: stiffnesses kn, ks (Pa/m), tensile strength ft
    and cohesion c (Pa), friction angle phi (deg), fracture energies GI, GII
    (N/m), and residual = tan(phi_r) / tan(phi), the residual friction
    that a damaged joint's friction falls to (kernels.joint_laws._coulomb_return;
    1: phi throughout), and the dilation angle psi (deg).  A law reads
    only the fields its table entry names."""
    kn: float
    ks: float
    ft: float = 0.0
    c: float = 0.0
    phi: float = 0.0
    GI: float = 0.0
    GII: float = 0.0
    residual: float = 1.0
    psi: float = 0.0

    def validate(self, where, law="coupled_softening"):
        for name in joint_law(law).fields + ("residual", "psi"):
            FIELD_RULES[name](self, f"{where}.{name}")

    def row(self):
        r = np.zeros(K.N_JP)
        r[K.JP_KN], r[K.JP_KS] = self.kn, self.ks
        r[K.JP_FT], r[K.JP_C] = self.ft, self.c
        r[K.JP_TANPHI] = math.tan(math.radians(self.phi))
        r[K.JP_TANPHI_R] = self.residual * r[K.JP_TANPHI]
        r[K.JP_TANPSI] = math.tan(math.radians(self.psi))
        r[K.JP_WU] = 2.0 * self.GI / self.ft if self.ft > 0 else 0.0
        r[K.JP_SU] = 2.0 * self.GII / self.c if self.c > 0 else 0.0
        return r
