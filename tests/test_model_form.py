"""The model-form options (config 'modelform'): the joint laws'
variants, residual friction, strips that turn, strips with friction, the
precompression platen, and the closed-form 3x3 algebra of the mesh.  Each
test states its closed form and tolerance."""
import math

import numpy as np
import pytest

from masonrydem.dem import Elastic, JointProps, Model
from masonrydem.dem import kernels as K
from masonrydem.dem.blocks import simpson, trapezoid
from masonrydem.dem.kernels.joint_laws import joint_bearing, joint_coupled, joint_coupled_additive, joint_coupled_total_slip
from masonrydem.dem.mesh import cofactors, det3
from masonrydem.dem.lockstep import drive
from masonrydem.specimen.protocol import precompress
from masonrydem.scene import build_scene
from masonrydem.dem import Numerics, init
from masonrydem.specimen.build import build
from masonrydem.dem.stops import Stops, run
from specimens import block_nodes, shear_joint, two_blocks, work

# the quasi-static integration these tests were written at (local damping 0.8)
QS = Numerics(damping=0.8, safety=0.9)

pytestmark = pytest.mark.verification

JOINT = JointProps(kn=1e11, ks=4e10, ft=0.3e6, c=0.36e6, phi=35.0, GI=9.0, GII=90.0)
TAN35 = math.tan(math.radians(35.0))
WILLIS = "config/scenes/willis.yaml"


def test_exponential_softening_dissipates_G_I():
    """A joint pulled apart with exponential softening: peak f_t A (2 %);
    after the peak the traction is f_t exp(-2 w_p / w_u), w_u = 2 G_I / f_t
    (1 % of f_t), and the work of the pull to 5 w_u is G_I A (1 - e^-10)
    plus the elastic energy still stored (2 %)."""
    m, lower, upper = two_blocks("coupled_exponential", JOINT)
    m.fix(block_nodes(m, lower))
    up = block_nodes(m, upper)
    m.fix(up, dofs=(0, 1, 2), velocity=(0.0, 0.0, 4e-9))
    m.add_monitor("pull", up, 2)
    wu = 2 * JOINT.GI / JOINT.ft
    state, rec, _ = run(init(m.build(), QS), 200_000, Stops(disp_limit=5 * wu, monitor="pull"), record_every=1)
    P, A = rec.history.force[:, 0], 0.01
    assert P.max() == pytest.approx(JOINT.ft * A, rel=0.02)
    wp = state.joints.state[:, K.JS_WP].mean()
    sn = state.joints.state[:, K.JS_SN].mean()
    assert sn == pytest.approx(JOINT.ft * math.exp(-2 * wp / wu), abs=0.01 * JOINT.ft)
    assert work(rec.history) == pytest.approx(JOINT.GI * A * (1 - math.exp(-2 * wp / wu))
                                              + sn ** 2 / (2 * JOINT.kn) * A, rel=0.02)


def _law(law, props, increments):
    """Runs the kernel law on one sub-contact through the increments
    (du_n, du_s) from zero; returns its last state."""
    p = tuple(props.row())
    st = (0.0,) * K.N_JS
    for dun, dus in increments:
        st = law(p, st, dun, dus, 0.0)
    return st


def test_lourenco_rots_coupling_sums_opening_and_slip():
    """A joint opened past its strength, then slipped: with Lourenco and
    Rots's coupling one parameter softens both strengths, D = w_p / w_u +
    s_p / s_u; ours multiplies the intact shares, D = 1 - (1 - w_p / w_u)
    (1 - s_p / s_u), less than the sum (1e-12)."""
    wu, su = 2 * JOINT.GI / JOINT.ft, 2 * JOINT.GII / JOINT.c
    steps = [(JOINT.ft / JOINT.kn + 0.2 * wu, 0.0)] + [(0.0, 0.02 * su)] * 20
    for law, combine in ((joint_coupled_additive, lambda a, b: min(a + b, 1.0)),
                         (joint_coupled, lambda a, b: 1 - (1 - a) * (1 - b))):
        st = _law(law, JOINT, steps)
        xt, xs = st[K.JS_WP] / wu, st[K.JS_SP] / su
        assert xt > 0.1 and xs > 0.1
        assert st[K.JS_D] == pytest.approx(combine(xt, xs), abs=1e-12)
    assert _law(joint_coupled_additive, JOINT, steps)[K.JS_D] > _law(joint_coupled, JOINT, steps)[K.JS_D]


def test_total_slip_counts_the_elastic_slip():
    """Shear softening over the total slip: after a slip past the peak,
    D = (s_p + |tau| / k_s) / s_u (1e-12), more than over the plastic slip
    alone by the elastic slip's share."""
    su = 2 * JOINT.GII / JOINT.c
    steps = [(0.0, 0.05 * su)] * 4
    st = _law(joint_coupled_total_slip, JOINT, steps)
    tau = math.hypot(st[K.JS_T1], st[K.JS_T2])
    assert st[K.JS_D] == pytest.approx((st[K.JS_SP] + tau / JOINT.ks) / su, abs=1e-12)
    assert st[K.JS_D] > _law(joint_coupled, JOINT, steps)[K.JS_D]


def test_dilation_presses_a_slipping_joint_together():
    """A joint held at a fixed normal displacement under compression, then
    slipped: each plastic slip ds_p adds k_n tan(psi) ds_p of compression
    (1e-9 relative); without dilation sigma_n stays (exactly)."""
    dun = -0.5e6 / JOINT.kn
    steps = [(dun, 0.0)] + [(0.0, 2e-5)] * 10
    sn0 = _law(joint_coupled, JOINT, steps[:1])[K.JS_SN]
    assert _law(joint_coupled, JOINT, steps)[K.JS_SN] == sn0
    props = JointProps(**{**JOINT.__dict__, "psi": 20.0})
    st = _law(joint_coupled, props, steps)
    assert st[K.JS_SP] > 0
    expected = sn0 - JOINT.kn * math.tan(math.radians(20.0)) * st[K.JS_SP]
    assert st[K.JS_SN] == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("n", [1, 2, 4])
def test_vertex_rule_overestimates_the_second_moment(n):
    """3DEC's nodal rule (blocks.trapezoid) on n intervals of [-1, 1]:
    weights sum to 2, the first moment is 0, and the second moment (a
    joint's bending stiffness and cracking moment) is (2/3)(1 + 2/n^2),
    where the Simpson rule is exact, 2/3 (1e-12)."""
    breaks = np.linspace(-1.0, 1.0, n + 1)
    for rule, second in ((trapezoid, 2 / 3 * (1 + 2 / n ** 2)), (simpson, 2 / 3)):
        x, w = rule(breaks)
        assert (w.sum(), w @ x, w @ x ** 2) == pytest.approx((2.0, 0.0, second), abs=1e-12)


def test_residual_friction():
    """A joint sheared under 0.2 MPa with tan(phi_r) = 0.5 tan(phi): peak
    c + sigma tan(phi) (2 %), residual sigma tan(phi_r) (2 %)."""
    props = JointProps(**{**JOINT.__dict__, "residual": 0.5})
    sigma = 0.2e6
    state, H, A = shear_joint(props, sigma, rate=1e-8)
    P = H.force[:, 0]
    assert P.max() == pytest.approx((JOINT.c + sigma * TAN35) * A, rel=0.02)
    assert P[-1] == pytest.approx(0.5 * sigma * TAN35 * A, rel=0.02)


def test_slip_scale_over_the_whole_peak():
    """With the slip scale s_u = 2 G_II / (c + sigma tan(phi)) (friction in
    the peak), the cohesion c softens over a shorter slip: it dissipates
    c s_u / 2 = G_II c / (c + sigma tan(phi)), and the work of the shear
    load under sigma = 0.2 MPa is that plus the friction work on the
    plastic slip and the elastic energy still stored (2 %)."""
    sigma = 0.2e6
    state, H, A = shear_joint(JOINT, sigma, rate=1e-8, law="coupled_friction_slip")
    tau_res = sigma * TAN35
    sp = state.joints.state[:, K.JS_SP].mean()
    expected = (JOINT.GII * JOINT.c / (JOINT.c + tau_res) + tau_res * sp + tau_res ** 2 / (2 * JOINT.ks)) * A
    assert work(H) == pytest.approx(expected, rel=0.02)
    assert H.force[-1, 0] == pytest.approx(tau_res * A, rel=0.02)


def test_strip_friction_is_coulomb():
    """A bearing pressed by 1e-6 m and then slid: |tau| = k_s du_s until
    it reaches tan(phi) |sigma_n|, and stays there; a frictionless bearing
    (k_s = tan(phi) = 0) carries no shear; neither carries tension."""
    row = np.zeros(K.N_JP)
    row[K.JP_KN] = row[K.JP_KS] = 1e11
    row[K.JP_TANPHI] = 0.5
    st = (0.0,) * K.N_JS
    st = joint_bearing(tuple(row), st, -1e-6, 0.0, 0.0)
    assert st[K.JS_SN] == pytest.approx(-1e5)
    st1 = joint_bearing(tuple(row), st, 0.0, 2e-7, 0.0)
    assert st1[K.JS_T1] == pytest.approx(2e4)
    st2 = joint_bearing(tuple(row), st1, 0.0, 1e-5, 0.0)
    assert st2[K.JS_T1] == pytest.approx(0.5e5)
    row[K.JP_KS] = row[K.JP_TANPHI] = 0.0
    assert joint_bearing(tuple(row), st, 0.0, 1e-5, 0.0)[K.JS_T1] == 0.0
    assert joint_bearing(tuple(row), st, 2e-6, 0.0, 0.0)[K.JS_SN] == 0.0


def _strip_resultant_x(state, strip):
    """x of the resultant of a strip's normal forces (sigma_n times area
    at each sub-contact's initial point: the displacements are 1e-4 of the
    tolerances)."""
    s = strip.sc
    fn = state.bearings.state[s, K.JS_SN] * state.bearings.area[s]
    return float(np.sum(fn * state.assembly.bearing_points[s, 0]) / np.sum(fn))


@pytest.mark.parametrize("rigid", [False, True])
def test_a_turning_strip_acts_on_its_centre_line(rigid):
    """A beam 1 m long bent by a load strip at mid-span between two support
    strips 40 mm wide: a roller turns with the beam, so its resultant lies
    on its centre line (zero moment about it: within 0.5 mm); a strip
    that only translates takes the beam's turn at its edge (more than 5 mm
    off its line).  Rigid blocks: two blocks hinged by a joint at mid-span."""
    offsets = {}
    for turns in (True, False):
        m = Model()
        mat = Elastic(E=1e9, nu=0.2)
        if rigid:
            for x0 in (0.0, 0.5):
                m.add_box([x0, 0, 0], [x0 + 0.5, 0.1, 0.1], (4, 2, 2), mat, rigid=True)
            m.set_joints("elastic", JointProps(kn=1e11, ks=4e10))
            for b in m.blocks:
                m.fix([b.node0], dofs=[2])
                m.fix_rotation(b, dofs=(0, 1))
            m.fix([m.blocks[0].node0], dofs=[0])
        else:
            m.add_box([0, 0, 0], [1.0, 0.1, 0.1], (20, 2, 2), mat)
            base = m.select(lambda x: x[:, 2] < 1e-9)
            m.fix(base, dofs=[2])
            m.fix(base[:1], dofs=[0])
        strips = [m.add_strip(f"support{i}", 1, 0.1, +1, ((0.0, 0.1), (x - 0.02, x + 0.02)), 1e11, turns=turns)
                  for i, x in enumerate((0.1, 0.9))]
        load = m.add_strip("load", 1, 0.0, -1, ((0.0, 0.1), (0.48, 0.52)), 1e11, velocity=(0, 1e-8, 0), turns=turns)
        m.add_monitor("load", [load], 1)
        state, _, _ = run(init(m.build(), QS), 20_000, Stops(disp_limit=2e-5, monitor="load"))
        offsets[turns] = [abs(_strip_resultant_x(state, s) - x) for s, x in zip(strips, (0.1, 0.9))]
    assert max(offsets[True]) < 5e-4, offsets
    assert min(offsets[False]) > 5e-3, offsets


def test_a_platen_keeps_the_top_course_plane():
    """The wallette precompressed to 0.5 MPa through a platen: the base
    carries sigma_v times the top course's plan area (1e-3), and the top
    faces under the platen, a rigid plate, settle by one amount up to the
    compliance of its bearing: their spread of vertical displacement is at
    most the spread of its bearing stresses over k_n (1e-3 relative), less
    than under the pressure of the spreader."""
    spreads = {}
    for platen in (True, False):
        scene = build_scene(WILLIS, ["physics.blocks=elastic", "numerics.cells=[2, 1, 1]",
                                    "loading.precompression.pressure=0.5e6",
                                    f"loading.precompression.platen={str(platen).lower()}"])
        spec = build(scene)
        state, outcome = drive(precompress(init(spec.assembly, QS), spec))
        a, g = spec.assembly, scene.geometry
        top = np.flatnonzero((np.abs(a.nodes.x0[:, 2] - g.height) < 1e-9) & (a.block_of_node >= 0))
        lo, hi = g.course_span(g.courses - 2)
        under = top[(a.nodes.x0[top, 0] > lo + 1e-9) & (a.nodes.x0[top, 0] < hi - 1e-9)]
        uz = state.nodes.u[under, 2]
        spreads[platen] = float(uz.max() - uz.min())
        if platen:
            base = np.flatnonzero((a.nodes.x0[:, 2] < 1e-9) & (a.block_of_node >= 0))
            L, T, _ = g.modelled_unit
            assert abs(state.nodes.f[base, 2].sum()) == pytest.approx(0.5e6 * g.units_per_course * L * T, rel=1e-3)
            plate = next(s for s in a.strips if s.name == "platen")
            sn = state.bearings.state[plate.sc, K.JS_SN]
            assert spreads[True] <= 1.001 * (sn.max() - sn.min()) / plate.kn
    assert spreads[True] < spreads[False], spreads


def test_closed_form_inverse_and_determinant():
    """cof(E)^T / det(E) is E's inverse (E E^-1 = I to 1e-12) and det(E)
    the triple product e_0 . (e_1 x e_2), for random and nearly flat
    matrices."""
    rng = np.random.default_rng(3)
    e = rng.standard_normal((200, 3, 3))
    e[:20, 2] = e[:20, 0] + 1e-6 * rng.standard_normal((20, 3))
    d = det3(e)
    assert np.allclose(d, np.einsum("ni,ni->n", e[:, 0], np.cross(e[:, 1], e[:, 2])), rtol=1e-9, atol=1e-15)
    inv = np.transpose(cofactors(e), (0, 2, 1)) / d[:, None, None]
    assert np.allclose(np.einsum("nij,njk->nik", e[20:], inv[20:]), np.eye(3), atol=1e-12)
