"""Specimens: a typed scene (masonrydem.scene) built into an assembled
model: units in running bond, joints with their properties, the test's
supports and drive (four-point bending, direct tension, triplet shear) and
the precompression.  The one place a Scene's names (block models, their
materials, its integration) become the solver's types."""
from dataclasses import dataclass

import numpy as np

from ..dem import GEOM_TOL, Assembly, Elastic, JointProps, Model, MohrCoulomb, Numerics
from ..errors import InputError
from ..scene import Scene, crack_stiffness, flexural_strength, joint_kn, joint_stiffness

# a block model's material (scene.BLOCK_MODELS names it) -> the solver's class
MATERIALS = {"elastic": Elastic, "mohr-coulomb": MohrCoulomb}


@dataclass(frozen=True)
class Specimen:
    """A scene's model, assembled, and what the protocol and the
    classification need to read it: units, joints, the drive."""
    scene: Scene
    assembly: Assembly
    units: tuple              # (course, index) of unit u
    block_unit: np.ndarray    # unit of each block (two per unit with potential-crack interfaces)
    joints: tuple             # (kind, (course, index)) of joint j: head, bed, then the units' crack interfaces
    contact_joint: np.ndarray  # joint number of each contact of the assembly
    drive: np.ndarray         # nodes whose prescribed velocity drives the test (the 'load' monitor's)
    velocity: np.ndarray      # their velocity in the loading stage (m per step)
    numerics: Numerics        # how the solver integrates it (the scene's integration)

    @property
    def test(self):
        return self.scene.loading.test

    def strength(self, P):
        """The test's load P (N) as a stress (Pa).  Bending: the flexural
        strength sigma = 6 M / (b h^2), M = P/2 a (docs/study.md, 2);
        tension: P over the gross section (wall height x thickness);
        triplet: the shear stress P / 2A on the two bed joints."""
        g = self.scene.geometry
        L, T, H = g.modelled_unit
        if self.test == "tension":
            return P / (g.courses * H * T)
        if self.test == "triplet":
            return P / (2.0 * L * T)
        bend = self.scene.loading.bending
        return flexural_strength(P, bend.shear_span, bend.section, g.unit_width)


def build(scene):
    """Builds and assembles the specimen of a typed scene."""
    m, units, block_unit = _units(scene)
    joints = list(scene.geometry.joints) + ([("crack", u) for u in units] if scene.physics.model.crack_interface
                                            else [])
    joint_of = _joint_numbering(units, block_unit, joints)
    props = _joint_props(scene, units, block_unit, joint_of)
    refine = scene.discretization.refine
    m.set_joints(scene.physics.joints, props, refine=lambda a, b: getattr(refine, joints[joint_of(a, b)][0]),
                 strip_refine=refine.strips, rule=scene.discretization.rule)
    drive, velocity = _test(m, scene, units, block_unit)
    _precompression(m, scene)
    if scene.physics.gravity:
        m.gravity = np.array([0.0, 0.0, -9.81])
    a = m.build()
    if scene.loading.test == "bending":     # the drive is the load strips: their nodes
        drive = a.strip_nodes[[s.index for s in drive]]
    contact_joint = np.array([joint_of(a.blocks[c.block_a], a.blocks[c.block_b]) for c in a.contacts])
    missing = sorted(set(range(len(joints))) - set(contact_joint.tolist()))
    if missing:
        raise InputError("geometry", f"joints {missing} touch no unit pair; check the bond")
    numerics = Numerics(damping=scene.integration.damping, safety=scene.integration.safety)
    return Specimen(scene, a, tuple(units), block_unit, tuple(joints), contact_joint, drive, velocity, numerics)


def _units(scene):
    """The model with its units: per unit one block or, with a crack
    interface, two meeting at its crack plane."""
    g, mat = scene.geometry, scene.materials.units
    L, T, H = g.modelled_unit
    model = scene.physics.model
    m = Model()
    m.large = scene.physics.large
    cells = scene.discretization.cells
    material_of = MATERIALS[model.material].of
    element = scene.discretization.elastic_element if model.material == "elastic" and not model.rigid else "zones"
    units, block_unit = [], []
    for k in range(g.courses):
        x0 = g.course_span(k)[0]
        spans = g.unit_spans(k)
        for i, (start, end) in enumerate(spans):
            uid = len(units)
            material = material_of(E=mat.E[uid], nu=mat.nu, density=mat.density, ft=mat.ft[uid], c=mat.c[uid],
                                         phi=mat.phi, Gf=float(mat.Gf[uid]))
            # a whole unit cracks in line with the head joints above and
            # below; a cut one (straight ends) at its middle
            whole = len(spans) == g.units_per_course
            at, length = (x0 + i * L, L) if whole else (start, end - start)
            plane = (g.crack_plane(k) if whole else 0.5 * length) if model.crack_interface else None
            for lo, hi, n in _pieces(at, length, plane, cells[0]):
                m.add_box([lo, 0.0, k * H], [hi, T, (k + 1) * H], [n, cells[1], cells[2]], material,
                          rigid=model.rigid, element=element)
                block_unit.append(uid)
            units.append((k, i))
    return m, units, np.asarray(block_unit)


def _joint_numbering(units, block_unit, joints):
    """joint_of(a, b): the joint number of the contact between blocks a and b."""
    index = {j: n for n, j in enumerate(joints)}

    def joint_of(a, b):
        ua, ub = block_unit[a.id], block_unit[b.id]
        if ua == ub:
            return index[("crack", units[ua])]
        (ka, ia), (kb, ib) = units[ua], units[ub]
        if ka == kb:
            return index[("head", (ka, min(ia, ib)))]
        return index[("bed", units[ua] if ka > kb else units[ub])]
    return joint_of


def _joint_props(scene, units, block_unit, joint_of):
    """props(a, b): a mortar joint's stiffness follows the mean E_b of the
    two units it connects, its strength and fracture energies its own
    field values; a unit's crack interface has the unit's strengths (f_tu,
    c_u, phi_u) and fracture energy G_fu (G_II in the joints' ratio)
    (masonry.py)."""
    mu, mj = scene.materials.units, scene.materials.joints
    L = scene.geometry.modelled_unit[0]
    t = scene.geometry.joint_thickness

    def props(a, b):
        ua, ub = block_unit[a.id], block_unit[b.id]
        if ua == ub:
            kn, ks = crack_stiffness(mu.E[ua], L, mu, mj)
            return JointProps(kn=kn, ks=ks, ft=mu.ft[ua], c=mu.c[ua], phi=mu.phi, GI=mu.Gf[ua],
                              GII=mj.GII_ratio * mu.Gf[ua], psi=mu.psi)
        j = joint_of(a, b)
        kn, ks = joint_stiffness(mu.E[ua], mu.E[ub], mj, t)
        return JointProps(kn=kn, ks=ks, ft=mj.ft[j], c=mj.c[j], phi=mj.phi[j], GI=mj.GI[j], GII=mj.GII[j],
                          residual=mj.residual_friction_ratio)
    return props


def _pieces(x0, L, plane, n):
    """The unit [x0, x0 + L] as one block of n cells along its length, or,
    with a crack plane at x0 + plane, as two blocks meeting there, the n
    cells shared in proportion (at least one each)."""
    if plane is None:
        return [(x0, x0 + L, n)]
    n1 = min(max(1, round(n * plane / L)), max(1, n - 1))
    return [(x0, x0 + plane, n1), (x0 + plane, x0 + L, max(1, n - n1))]


def _test(m, scene, units, block_unit):
    """The test's supports, drive and monitors ('load': the drive's
    reaction and displacement; 'support': the reaction that balances it).
    Returns the drive (bending: the load strips; else nodes) and its
    velocity in the loading stage."""
    if scene.loading.test == "bending":
        return _bending(m, scene)
    g, test = scene.geometry, scene.loading.test
    first = {units[block_unit[blk.id]]: blk for blk in m.blocks[::-1]}    # a unit's (left) first block
    last = {units[block_unit[blk.id]]: blk for blk in m.blocks}           # and its (right) last one
    rigid = scene.physics.model.rigid
    # base roller; y held at one base node (rigid units: the bottom left
    # unit); x is held by the grips
    _roller(m, rigid, m.blocks[0].lo, dof=1)
    if test == "tension":   # every course gripped at both ends
        held = _grip(m, [first[(k, 0)] for k in range(g.courses)], 0)
        pulled = [last[(k, g.units_per_course - 1)] for k in range(g.courses)]
    else:                   # triplet: outer units held on the right, the middle one pushed on the left
        held, pulled = _grip(m, [last[(0, 0)], last[(2, 0)]], 1), [first[(1, 0)]]
    m.fix(held, dofs=[0])
    drive = _grip(m, pulled, 0 if test == "triplet" else 1)
    m.fix(drive, dofs=[0])
    m.add_monitor("load", drive, 0)
    m.add_monitor("support", held, 0)
    return drive, np.array([scene.loading.drive.rate, 0.0, 0.0])


def _precompression(m, scene):
    """sigma_v on the top course, or with a spreader on the part of it that
    bears on the course below (schema: loading.precompression.spreader), as
    a pressure or through a platen (loading.precompression.platen)."""
    pre, g = scene.loading.precompression, scene.geometry
    if not pre.pressure:
        return
    nk = g.courses
    lo, hi = g.course_span(nk - 1)
    if pre.spreader and nk > 1:
        below = g.course_span(nk - 2)
        lo, hi = max(lo, below[0]), min(hi, below[1])
    L, T, _ = g.modelled_unit
    rect = ((lo, hi), (-1.0, T + 1.0))
    if pre.platen:      # a rigid plate held down by the force, as stiff as the bending strips
        # (in vertical bending it turns with the wallette's top, as the base does)
        m.add_strip("platen", 2, g.height, +1, ((lo, hi), (0.0, T)), _strip_kn(scene),
                    force=(0.0, 0.0, -pre.pressure * g.units_per_course * L * T), turns=_spans_vertically(scene))
        return
    m.add_pressure(2, g.height, +1, rect, pre.pressure * g.units_per_course * L / (hi - lo))


def _roller(m, rigid, point, dof):
    """The base: a roller (z fixed) under the bottom face, and ``dof`` fixed
    at the base node nearest ``point`` (``_held``).  Rigid units: the
    roller holds each bottom unit's z and its rotations about x and y."""
    if rigid:
        for b in (b for b in m.blocks if b.lo[2] < GEOM_TOL):
            m.fix([b.node0], dofs=[2])
            m.fix_rotation(b, dofs=(0, 1))
    else:
        m.fix(m.select(lambda x: x[:, 2] < GEOM_TOL), dofs=[2])
    _held(m, rigid, point, dof)


def _held(m, rigid, point, dof):
    """``dof`` fixed at the base node nearest ``point`` (the least restraint
    against rigid motion; a line of fixed nodes would add stiffness); rigid
    units: at the node of the bottom unit nearest it in plan."""
    if rigid:
        bottom = [b for b in m.blocks if b.lo[2] < GEOM_TOL]
        nearest = min(bottom, key=lambda b: np.linalg.norm(b.centroid[:2] - point[:2]))
        m.fix([nearest.node0], dofs=[dof])
    else:
        base = m.select(lambda x: x[:, 2] < GEOM_TOL)
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


def _spans_vertically(scene):
    return scene.loading.test == "bending" and scene.loading.bending.direction == "vertical"


def _strip_kn(scene):
    """A strip's k_n: strip_stiffness_ratio joints between units of the
    wall's mean E_b."""
    g = scene.geometry
    return scene.loading.bending.strip_stiffness_ratio * joint_kn(
        float(np.mean(scene.materials.units.E)), scene.materials.joints.Em_ratio, g.joint_thickness)


def _bending(m, scene):
    """Four-point out-of-plane bending (docs/study.md, 2; docs/formulation.md,
    8.1): support strips on the back face, load strips on the front face,
    as stiff as strip_stiffness_ratio joints between units of the wall's
    mean E_b, lines across the span (horizontal bending: over the wall's
    height at x; vertical: at heights z, over the stretch every course
    covers).  Horizontal: the base roller with x fixed at the node nearest
    the span centre at mid-thickness (on a head joint a line of x-fixed
    nodes would pin it shut; y is held by the strips).  Vertical: the base
    bears on a strip that turns about its long side, so that the foot
    turns with the span, and x is fixed at the base node nearest the
    middle of the common stretch at mid-thickness.  Returns the load
    strips and their velocity."""
    bend, g = scene.loading.bending, scene.geometry
    T, Htot = g.unit_width, g.height
    rigid = scene.physics.model.rigid
    w = 0.5 * bend.strip_width
    ks = _strip_kn(scene)
    how = dict(turns=bend.strips_turn, friction=bend.strip_friction)
    if bend.direction == "vertical":
        x0, x1 = g.common_span
        m.add_strip("base", 2, 0.0, -1, ((x0, x1), (0.0, T)), ks, turns=True)
        _held(m, rigid, np.array([0.5 * (x0 + x1), 0.5 * T, 0.0]), dof=0)
        # strips on planes normal to y: plane coordinates (p, q) = (z, x)
        def line(at):
            return (at - w, at + w), (x0, x1)
    else:
        _roller(m, rigid, np.array([np.mean(bend.supports), 0.5 * T, 0.0]), dof=0)

        def line(at):
            return (0.0, Htot), (at - w, at + w)
    supports = [m.add_strip(f"support{i}", 1, T, +1, line(at), ks, **how) for i, at in enumerate(bend.supports)]
    loads = [m.add_strip(f"load{i}", 1, 0.0, -1, line(at), ks, **how) for i, at in enumerate(bend.loads)]
    m.add_monitor("load", loads, 1)
    m.add_monitor("support", supports, 1)
    return loads, np.array([0.0, scene.loading.drive.rate, 0.0])
