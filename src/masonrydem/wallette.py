"""The Willis wallette (../shared/spec/study.md, sections 1-3): running-bond
brick wallette in four-point out-of-plane horizontal bending.

Axes: x along the wall (length), y through the thickness (out of plane),
z up.  Units are expanded by half a joint on each side (simplified
micro-model) and joints are zero-thickness interfaces.
"""
from dataclasses import dataclass

import numpy as np

from .laws import JointProps, MohrCoulomb
from .model import GEOM_TOL, Model


@dataclass
class WalletteSpec:
    # geometry (m)
    unit_length: float = 0.240
    unit_height: float = 0.075
    thickness: float = 0.114
    courses: int = 6
    units_per_course: int = 4
    cells: tuple = (4, 2, 2)            # per unit, along x, y, z
    # bricks
    E_b: float = 15e9
    nu_b: float = 0.2
    f_tu: float = 3.75e6
    c_u_ratio: float = 1.5
    phi_u: float = 35.0
    G_fu: float = 100.0
    # joints
    joint_thickness: float = 0.010
    E_m_ratio: float = 0.1
    ks_ratio: float = 0.4
    f_tj: float = 0.30e6
    c_j_ratio: float = 1.2
    phi_j: float = 35.0
    G_fj_I: float = 9.0
    G_fj_II_ratio: float = 10.0
    joint_law: str = "coupled_softening"
    # loading
    supports_x: tuple = (0.135, 0.945)
    loads_x: tuple = (0.410, 0.670)
    strip_width: float = 0.020
    strip_stiffness_ratio: float = 10.0  # strip k_n / joint k_n
    precompression: float = 0.0          # Pa


def joint_kn(E_b, E_m_ratio, t):
    """k_n = E_b E_m / (t (E_b - E_m)), E_m = ratio E_b (study.md, 3)."""
    E_m = E_m_ratio * E_b
    return E_b * E_m / (t * (E_b - E_m))


def build(spec: WalletteSpec):
    """Model of the wallette with supports, load strips and precompression.
    Returns (model, handles) with handles: 'load' (monitor name), the strip
    objects 'loads' and 'supports'."""
    m = Model()
    brick = MohrCoulomb(E=spec.E_b, nu=spec.nu_b, ft=spec.f_tu, c=spec.c_u_ratio * spec.f_tu,
                        phi=spec.phi_u, Gf=spec.G_fu)
    L, H, T = spec.unit_length, spec.unit_height, spec.thickness
    for k in range(spec.courses):
        x0 = 0.5 * L if k % 2 else 0.0
        for i in range(spec.units_per_course):
            m.add_box([x0 + i * L, 0.0, k * H], [x0 + (i + 1) * L, T, (k + 1) * H], spec.cells, brick)
    kn = joint_kn(spec.E_b, spec.E_m_ratio, spec.joint_thickness)
    props = JointProps(kn=kn, ks=spec.ks_ratio * kn, ft=spec.f_tj, c=spec.c_j_ratio * spec.f_tj,
                       phi=spec.phi_j, GI=spec.G_fj_I, GII=spec.G_fj_II_ratio * spec.G_fj_I)
    m.set_joints(spec.joint_law, props)
    # base: roller (z fixed); x fixed on the base line at mid-length (no
    # stiffness added against bending about z); y is held by the strips
    m.fix(m.select(lambda x: x[:, 2] < GEOM_TOL), dofs=[2])
    xmid = 0.5 * spec.units_per_course * L
    base_mid = m.select(lambda x: (x[:, 2] < GEOM_TOL) & (np.abs(x[:, 0] - xmid) < GEOM_TOL))
    m.fix(base_mid, dofs=[0])
    Htot = spec.courses * H
    w = 0.5 * spec.strip_width
    ks = spec.strip_stiffness_ratio * kn
    # strips on planes normal to y: plane coordinates (p, q) = (z, x)
    supports = [m.add_strip(f"support{i}", 1, T, +1, ((0.0, Htot), (x - w, x + w)), ks)
                for i, x in enumerate(spec.supports_x)]
    loads = [m.add_strip(f"load{i}", 1, 0.0, -1, ((0.0, Htot), (x - w, x + w)), ks)
             for i, x in enumerate(spec.loads_x)]
    m.add_monitor("load", loads, 1)
    if spec.precompression:
        top_x = (-1.0, spec.units_per_course * L + L)
        m.add_pressure(2, Htot, +1, (top_x, (-1.0, T + 1.0)), spec.precompression)
    return m, dict(load="load", loads=loads, supports=supports)


def bending_moment_arm(spec: WalletteSpec):
    """Shear span a; M = P/2 a for a total load P."""
    return spec.loads_x[0] - spec.supports_x[0]
