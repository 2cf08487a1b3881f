"""Specimens: a validated scene (scene.py) built into a Model: units in
running bond, joints with their properties, the test's supports and
drive (four-point bending, direct tension, triplet shear) and the
precompression."""
from dataclasses import dataclass

import numpy as np

from .blocks import GEOM_TOL
from .errors import InputError
from .laws import BLOCK_MODELS, Elastic, JointProps
from .masonry import (course_span, crack_plane, flexural_strength, joint_kn, modelled_unit, running_bond_joints,
                      unit_fracture_energy)
from .model import Model


@dataclass
class Specimen:
    """What ``build`` returns beside the model."""
    model: Model
    scene: dict
    units: list            # (course, index) of unit u
    block_unit: np.ndarray  # unit of each block (two per unit with potential-crack interfaces)
    joints: list           # (kind, (course, index)) of joint j: head, bed, then the units' crack interfaces
    contact_joint: np.ndarray   # joint number of each model contact
    drive: np.ndarray      # nodes whose prescribed velocity drives the test (the 'load' monitor's)
    velocity: np.ndarray   # their velocity in the loading stage (m per step)
    supports: list         # bending: the support strips
    E_b: np.ndarray        # per unit
    f_tu: np.ndarray
    f_tj: np.ndarray       # per joint
    phi_j: np.ndarray

    @property
    def test(self):
        return self.scene["loading"]["test"]

    @property
    def stage(self):
        """The loading stage's settings (rate, ramp, stop criteria)."""
        return self.scene["loading"][self.test]

    @property
    def shear_span(self):
        b = self.scene["loading"]["bending"]
        return min(b["loads_x"]) - min(b["supports_x"])


def _per(values, n, default):
    return np.asarray(values, float) if values is not None else np.full(n, float(default))


def build(scene):
    """Builds the specimen of a validated scene: units, joints with their
    properties, supports and load strips, precompression."""
    g, mat, phys = scene["geometry"], scene["materials"], scene["physics"]
    L, T, H = modelled_unit(g)
    nk, nu = g["courses"], g["units_per_course"]
    mu, mj = mat["units"], mat["joints"]
    per_u, per_j = mat.get("per_unit", {}), mat.get("per_joint", {})
    n_units = nk * nu
    E_b = _per(per_u.get("E"), n_units, mu["E"])
    f_tu = _per(per_u.get("ft"), n_units, mu["ft"])
    joints = running_bond_joints(nk, nu)
    f_tj = _per(per_j.get("ft"), len(joints), mj["ft"])
    phi_j = _per(per_j.get("phi"), len(joints), mj["phi"])

    m = Model()
    model = BLOCK_MODELS[phys["blocks"]]
    rigid = model.rigid
    m.large = phys["displacements"] == "large"
    units, block_unit, Gf = [], [], np.zeros(n_units)
    cells = scene["numerics"]["cells"]
    element = scene["numerics"]["elastic_element"] if model.material is Elastic and not rigid else "zones"
    for k in range(nk):
        x0 = course_span(g, k)[0]
        for i in range(nu):
            uid = len(units)
            Gf[uid] = mu["Gf"]
            if "gf_coefficient" in per_u:
                Gf[uid] = float(unit_fracture_energy(f_tu[uid], per_u["gf_coefficient"], per_u["gf_exponent"]))
            material = model.material.of(E=E_b[uid], nu=mu["nu"], density=mu["density"], ft=f_tu[uid],
                                         c=mu["c_ratio"] * f_tu[uid], phi=mu["phi"], Gf=float(Gf[uid]))
            for lo, hi, n in _pieces(x0 + i * L, L, crack_plane(g, k) if model.crack_interface else None, cells[0]):
                m.add_box([lo, 0.0, k * H], [hi, T, (k + 1) * H], [n, cells[1], cells[2]], material, rigid=rigid,
                          element=element)
                block_unit.append(uid)
            units.append((k, i))
    if model.crack_interface:
        joints = joints + [("crack", u) for u in units]
    block_unit = np.asarray(block_unit)

    def joint_of(a, b):
        """Joint number of the contact between blocks a and b."""
        ua, ub = block_unit[a.id], block_unit[b.id]
        if ua == ub:
            return joints.index(("crack", units[ua]))
        (ka, ia), (kb, ib) = units[ua], units[ub]
        if ka == kb:
            return joints.index(("head", (ka, min(ia, ib))))
        return joints.index(("bed", units[ua] if ka > kb else units[ub]))

    t = g["joint_thickness"]

    def props(a, b):
        """A joint's stiffness follows the mean E_b of the two units it
        connects; its strength and fracture energies follow its f_tj.  A
        unit's crack interface has the unit's strengths (f_tu, c_u, phi_u)
        and fracture energy G_fu (G_II in the joints' ratio), and a
        stiffness crack_kn_ratio E_b / L."""
        ua, ub = block_unit[a.id], block_unit[b.id]
        if ua == ub:
            kn = mu["crack_kn_ratio"] * E_b[ua] / L
            return JointProps(kn=kn, ks=mj["ks_ratio"] * kn, ft=f_tu[ua], c=mu["c_ratio"] * f_tu[ua], phi=mu["phi"],
                              GI=Gf[ua], GII=mj["GII_ratio"] * Gf[ua])
        j = joint_of(a, b)
        kn = joint_kn(0.5 * (E_b[ua] + E_b[ub]), mj["Em_ratio"], t)
        ft = f_tj[j]
        GI = per_j["gi_per_ft"] * ft if "ft" in per_j else mj["GI"]
        return JointProps(kn=kn, ks=mj["ks_ratio"] * kn, ft=ft, c=mj["c_ratio"] * ft, phi=phi_j[j],
                          GI=GI, GII=mj["GII_ratio"] * GI)

    kind_refine = refine_by_kind(scene["numerics"]["subcontact_refine"])
    m.set_joints(phys["joints"], props, refine=lambda a, b: kind_refine[joints[joint_of(a, b)][0]],
                 strip_refine=kind_refine["strips"])
    test = scene["loading"]["test"]
    Htot = nk * H
    first = {units[block_unit[blk.id]]: blk for blk in m.blocks[::-1]}    # a unit's (left) first block
    last = {units[block_unit[blk.id]]: blk for blk in m.blocks}           # and its (right) last one
    if test == "bending":
        drive, velocity, supports = _bending(m, scene, rigid, T, Htot, E_b)
    else:
        # base roller; y held at one base node (rigid units: the bottom
        # left unit); x is held by the grips
        _roller(m, rigid, m.blocks[0].lo, dof=1)
        if test == "tension":   # every course gripped at both ends
            held, pulled = _grip(m, [first[(k, 0)] for k in range(nk)], 0), [last[(k, nu - 1)] for k in range(nk)]
        else:                   # triplet: outer units held on the right, the middle one pushed on the left
            held, pulled = _grip(m, [last[(0, 0)], last[(2, 0)]], 1), [first[(1, 0)]]
        m.fix(held, dofs=[0])
        drive = _grip(m, pulled, 0 if test == "triplet" else 1)
        m.fix(drive, dofs=[0])
        m.add_monitor("load", drive, 0)
        m.add_monitor("support", held, 0)
        velocity, supports = np.array([scene["loading"][test]["rate"], 0.0, 0.0]), []
    pre = scene["loading"]["precompression"]
    if pre["pressure"]:
        # the top course, or with a spreader the part of it that bears on
        # the course below (schema: loading.precompression.spreader)
        lo, hi = course_span(g, nk - 1)
        if pre["spreader"] and nk > 1:
            below = course_span(g, nk - 2)
            lo, hi = max(lo, below[0]), min(hi, below[1])
        m.add_pressure(2, Htot, +1, ((lo, hi), (-1.0, T + 1.0)), pre["pressure"] * nu * L / (hi - lo))
    if phys["gravity"]:
        m.gravity = np.array([0.0, 0.0, -9.81])
    m.build()
    if test == "bending":   # the strips' nodes are numbered by build
        drive = np.array([strip.node for strip in drive], np.int64)
    contact_joint = np.array([joint_of(m.blocks[c.block_a], m.blocks[c.block_b]) for c in m.contacts])
    missing = sorted(set(range(len(joints))) - set(contact_joint.tolist()))
    if missing:
        raise InputError("geometry", f"joints {missing} touch no unit pair; check the bond")
    return Specimen(m, scene, units, block_unit, joints, contact_joint, drive, velocity, supports, E_b, f_tu, f_tj,
                    phi_j)


REFINE_KINDS = ("head", "bed", "crack", "strips")


def refine_by_kind(refine):
    """numerics.subcontact_refine per kind of contact (REFINE_KINDS), each
    one integer or one per axis: the scene's one value for all kinds, or
    its mapping (1 for a kind it does not name)."""
    if isinstance(refine, dict):
        return {k: refine.get(k, 1) for k in REFINE_KINDS}
    return dict.fromkeys(REFINE_KINDS, refine)


def _pieces(x0, L, plane, n):
    """The unit [x0, x0 + L] as one block of n cells along its length, or,
    with a crack plane at x0 + plane, as two blocks meeting there, the n
    cells shared in proportion (at least one each)."""
    if plane is None:
        return [(x0, x0 + L, n)]
    n1 = min(max(1, round(n * plane / L)), max(1, n - 1))
    return [(x0, x0 + plane, n1), (x0 + plane, x0 + L, max(1, n - n1))]


def _roller(m, rigid, point, dof):
    """The base: a roller (z fixed) under the bottom face, and ``dof`` fixed
    at the base node nearest ``point`` (the least restraint against rigid
    motion; a line of fixed nodes would add stiffness).  Rigid units: the
    roller holds each bottom unit's z and its rotations about x and y."""
    if rigid:
        bottom = [b for b in m.blocks if b.lo[2] < GEOM_TOL]
        for b in bottom:
            m.fix([b.node0], dofs=[2])
            m.fix_rotation(b, dofs=(0, 1))
        nearest = min(bottom, key=lambda b: np.linalg.norm(b.centroid[:2] - point[:2]))
        m.fix([nearest.node0], dofs=[dof])
    else:
        base = m.select(lambda x: x[:, 2] < GEOM_TOL)
        m.fix(base, dofs=[2])
        m.fix(base[np.argmin(np.linalg.norm(m.x0[base] - point, axis=1))], dofs=[dof])


def _grip(m, blocks, side):
    """The nodes of the end faces (normal to x; side 0 = low x, 1 = high x)
    of ``blocks``: a platen that holds or moves them along x.  A rigid
    unit: its node, with its rotations about y and z held (the platen
    keeps the face flat)."""
    nodes = []
    for b in blocks:
        if b.rigid:
            nodes.append(b.node0)
            m.fix_rotation(b, dofs=(1, 2))
        else:
            x = m.x0[b.node0:b.node0 + b.n_nodes, 0]
            nodes.extend(b.node0 + np.flatnonzero(np.abs(x - (b.hi[0] if side else b.lo[0])) < GEOM_TOL))
    return np.asarray(nodes, np.int64)


def _bending(m, scene, rigid, T, Htot, E_b):
    """Four-point out-of-plane bending (docs/study.md, 2): the base roller with x
    fixed at the node nearest the span centre at mid-thickness (on a head
    joint a line of x-fixed nodes would pin it shut; y is held by the
    strips), support strips on the back face, load strips on the front
    face.  Returns the load strips, their velocity and the supports."""
    bend, mj = scene["loading"]["bending"], scene["materials"]["joints"]
    _roller(m, rigid, np.array([np.mean(bend["supports_x"]), 0.5 * T, 0.0]), dof=0)
    w = 0.5 * bend["strip_width"]
    ks = bend["strip_stiffness_ratio"] * joint_kn(float(np.mean(E_b)), mj["Em_ratio"],
                                                  scene["geometry"]["joint_thickness"])
    # strips on planes normal to y: plane coordinates (p, q) = (z, x)
    supports = [m.add_strip(f"support{i}", 1, T, +1, ((0.0, Htot), (xs - w, xs + w)), ks)
                for i, xs in enumerate(bend["supports_x"])]
    loads = [m.add_strip(f"load{i}", 1, 0.0, -1, ((0.0, Htot), (xl - w, xl + w)), ks)
             for i, xl in enumerate(bend["loads_x"])]
    m.add_monitor("load", loads, 1)
    m.add_monitor("support", supports, 1)
    return loads, np.array([0.0, bend["rate"], 0.0]), supports


def strength(P, specimen):
    """The test's load as a stress.  Bending: the flexural strength
    sigma = 6 M / (b h^2), M = P/2 a (docs/study.md, 2); tension: P over the
    gross section (wall height x thickness); triplet: the shear stress
    P / 2A on the two bed joints."""
    g = specimen.scene["geometry"]
    L, T, H = modelled_unit(g)
    if specimen.test == "tension":
        return P / (g["courses"] * H * T)
    if specimen.test == "triplet":
        return P / (2.0 * L * T)
    return flexural_strength(P, specimen.shear_span, specimen.scene["loading"]["bending"]["section_height"],
                             g["unit"]["width"])
