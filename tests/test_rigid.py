"""Rigid blocks: six degrees of freedom per block, sub-contacts on
the block faces, large rotations; closed forms of rigid-block statics and
dynamics.  Each test states its formula and tolerance."""
import math

import numpy as np
import pytest

from masonrydem.dem import Elastic, JointProps, Model
from masonrydem.errors import InputError
from masonrydem.dem import kernels as K
from masonrydem.dem.kernels.joint_laws import joint_friction
from masonrydem.dem import Numerics, init, max_rotation, prescribe_rotation
from masonrydem.dem.stops import Stops, run

# the quasi-static integration these tests were written at (local damping 0.8)
QS = Numerics(damping=0.8, safety=0.9)

pytestmark = pytest.mark.verification

G = 9.81
RHO = 2000.0
MAT = Elastic(E=1e9, nu=0.2, density=RHO)   # E unused by rigid blocks


def _block_on_ground(b, d, h, phi, gravity, large=False):
    """A rigid block b x d x h (x, y, z) on a fixed rigid ground, a dry
    contact (law 'friction': no tension, no cohesion, a gap that must close
    before it carries compression again).  The ground's face grid is the
    finer, so it carries the sub-contacts (fixed axes: the ground's normal)."""
    m = Model()
    ground = m.add_box([-0.3, -0.3, -0.1], [0.3, 0.3, 0.0], (48, 48, 1), MAT, rigid=True)
    blk = m.add_box([-b / 2, -d / 2, 0.0], [b / 2, d / 2, h], (2, 2, 2), MAT, rigid=True)
    m.set_joints("friction", JointProps(kn=1e10, ks=1e10, phi=phi))
    m.fix([ground.node0])
    m.fix_rotation(ground)
    m.gravity = np.asarray(gravity, float)
    m.large = large
    m.add_monitor("block", [blk.node0], 0)
    return m, blk


def _tilted(psi_deg):
    """Gravity of an incline of slope psi (about y): the ground stays level."""
    psi = math.radians(psi_deg)
    return G * np.array([math.sin(psi), 0.0, -math.cos(psi)])


def test_rigid_model_has_no_zones_and_never_enters_the_zone_kernel():
    """A rigid-block model allocates no zones (no tetrahedra, no
    stresses), and the step kernel, specialised on rigid blocks, never
    enters the zone kernel: given zones whose every value is NaN (on body
    0), the run is the same bit for bit (entering them would turn every
    force non-finite)."""
    def solve(poison):
        m, blk = _block_on_ground(0.1, 0.1, 0.05, 30.0, _tilted(0.0))
        a = m.build()
        assert a.rigid and a.zones.tets.shape[0] == 0
        if poison:
            nan = np.full
            a.zones = K.Zones(tets=np.zeros((5, 4), np.int64), dn=nan((5, 9), np.nan), vol=nan(5, np.nan),
                              wt=nan(5, np.nan), gptr=np.array([0, 5]), gnodes=np.zeros(8, np.int64),
                              gnptr=np.array([0, 8]), par=nan((5, K.N_ZP), np.nan), state=nan((5, K.N_ZS), np.nan),
                              stress=nan((5, 6), np.nan))
        state = init(a, QS)
        assert poison or state.zones.stress.shape[0] == 0
        state, _, end = run(state, 50_000, Stops(ratio_tol=1e-6))
        assert end.status == "converged"
        return state
    clean, poisoned = solve(False), solve(True)
    assert np.isfinite(poisoned.nodes.u).all() and np.array_equal(clean.nodes.u, poisoned.nodes.u)
    assert np.array_equal(clean.bodies.R, poisoned.bodies.R)


def test_rigid_and_deformable_blocks_do_not_mix():
    m = Model()
    m.add_box([0, 0, 0], [0.1, 0.1, 0.1], (1, 1, 1), MAT, rigid=True)
    m.add_box([0, 0, 0.1], [0.1, 0.1, 0.2], (1, 1, 1), MAT)
    with pytest.raises(InputError, match="physics.blocks"):
        m.build()
    m = Model()
    m.add_box([0, 0, 0], [0.1, 0.1, 0.1], (1, 1, 1), MAT)
    m.large = True
    with pytest.raises(InputError, match="physics.displacements"):
        m.build()


def test_rigid_block_resting_carries_its_weight():
    """Level ground, vertical gravity: the block comes to rest (ratio < 1e-8)
    with the ground's contact force equal to its weight rho g V (1e-6)
    and no rotation."""
    m, blk = _block_on_ground(0.1, 0.1, 0.05, 30.0, [0.0, 0.0, -G])
    a = m.build()
    state, _, end = run(init(a, QS), 100_000, Stops(ratio_tol=1e-8))
    assert end.status == "converged"
    weight = RHO * 0.1 * 0.1 * 0.05 * G
    normal = -float(np.sum(state.joints.state[:, K.JS_SN] * a.joints.area))
    assert normal == pytest.approx(weight, rel=1e-6)
    assert max_rotation(state) < 1e-9


@pytest.mark.parametrize("psi", [29.0, 31.0])
def test_rigid_block_on_incline_rests_just_below_phi_and_slides_just_above(psi):
    """phi = 30 deg, the threshold bracketed within a degree: at 29 deg the
    block comes to rest (ratio < 1e-6) with a slide along the slope of the
    order of the elastic shear estimate W sin(psi) / (k_s A) (below 4 times
    it: the tilted weight also rocks it on its base); at 31 deg it never
    does, and slides on (over 1000 times the estimate in 200,000 steps)."""
    m, blk = _block_on_ground(0.1, 0.1, 0.05, 30.0, _tilted(psi))
    state, _, end = run(init(m.build(), QS), 200_000, Stops(ratio_tol=1e-6))
    weight = RHO * 0.1 * 0.1 * 0.05 * G
    slide = abs(state.nodes.u[blk.node0, 0]) / (weight * math.sin(math.radians(psi)) / (1e10 * 0.01))
    if psi < 30.0:
        assert end.status == "converged" and slide < 4.0
    else:
        assert end.status == "max_steps" and slide > 1000.0


def test_rigid_block_on_incline_slides_above_phi():
    """Slope 40 deg > phi = 30 deg, dynamic, undamped: the block slides with
    a = g (sin psi - cos psi tan phi) (2 %, quadratic fit of its
    displacement over 0.1 s)."""
    psi, phi = 40.0, 30.0
    m, blk = _block_on_ground(0.1, 0.1, 0.05, phi, _tilted(psi))
    state = init(m.build(), Numerics(mode="dynamic", safety=0.5))
    dt = state.integrator.dt
    state, rec, _ = run(state, int(0.1 / dt))
    H = rec.history
    acc = 2 * np.polyfit(H.step * dt, H.disp[:, 0], 2)[0]
    exact = G * (math.sin(math.radians(psi)) - math.cos(math.radians(psi)) * math.tan(math.radians(phi)))
    assert acc == pytest.approx(exact, rel=0.02)


@pytest.mark.parametrize("slenderness, topples", [(0.95, True), (1.05, False)])
def test_rigid_block_topples_when_width_over_height_is_below_tan_slope(slenderness, topples):
    """Slope psi = 30 deg, phi = 45 deg (no sliding), block of width
    b = slenderness * h tan(psi): the threshold b / h = tan(psi) bracketed
    within 5 %: it topples (rotation beyond 0.3 rad within 0.6 s, dynamic,
    undamped, large rotations) at 0.95 tan(psi), and stays upright
    (rotation below 0.01 rad) at 1.05 tan(psi).  (Closer to it, the weight
    applied at once rocks the block before it settles.)"""
    h = 0.2
    b = slenderness * h * math.tan(math.radians(30.0))
    m, blk = _block_on_ground(b, 0.1, h, 45.0, _tilted(30.0), large=True)
    state = init(m.build(), Numerics(mode="dynamic", safety=0.5))
    rot = 0.0
    for _ in range(60):
        state, _, _ = run(state, int(0.01 / state.integrator.dt))
        rot = max(rot, max_rotation(state))
        if rot > 0.3:
            break
    assert (rot > 0.3) if topples else (rot < 0.01)


def test_rocking_block_pushover_follows_tan_alpha_minus_theta():
    """Static pushover of a rigid block b x h on a rigid base under its
    weight W and a horizontal load lambda W at its centroid: held at a
    rotation theta about its edge, equilibrium needs
    lambda(theta) = tan(alpha - theta), tan(alpha) = b / h.  Under
    lambda0 = 0.2 the block is turned (quasi-static, large rotations,
    translations free) to theta = 0.05, 0.15 and 0.3 rad and held there
    until at rest (ratio < 1e-7); the moment C the hold supplies gives
    lambda(theta) = lambda0 + C / (W R cos(alpha - theta)), R the half
    diagonal (moments about the pivot edge): within 1 % of tan(alpha - theta)."""
    b, d, h, lam0 = 0.1, 0.1, 0.2, 0.2
    m, blk = _block_on_ground(b, d, h, 45.0, [lam0 * G, 0.0, -G], large=True)
    rate = 1e-5                                    # rad per step, about +y: tips toward +x
    m.fix_rotation(blk)
    state = init(m.build(), QS)
    W, R, alpha = RHO * b * d * h * G, 0.5 * math.hypot(b, h), math.atan2(b, h)
    for theta in (0.05, 0.15, 0.3):
        state = prescribe_rotation(state, blk, (0.0, rate, 0.0))
        state, _, _ = run(state, int(round((theta - max_rotation(state)) / rate)))
        state = prescribe_rotation(state, blk, (0.0, 0.0, 0.0))
        state, _, end = run(state, 500_000, Stops(ratio_tol=1e-7))
        assert end.status == "converged"
        assert max_rotation(state) == pytest.approx(theta, abs=1e-9)
        C = -state.bodies.mom[blk.node0, 1]
        lam = lam0 + C / (W * R * math.cos(alpha - theta))
        print(f"theta {theta}: lambda {lam:.5f}, tan(alpha - theta) {math.tan(alpha - theta):.5f}")
        assert lam == pytest.approx(math.tan(alpha - theta), rel=0.01), theta


def test_dry_contact_closes_its_gap_before_it_carries_compression():
    """Law 'friction': opened by w, the contact carries nothing until it
    has closed by w; then sigma_n = k_n e (e the penetration); shear is
    bounded by -sigma_n tan(phi) and is zero while open."""
    props = JointProps(kn=1e10, ks=4e9, phi=30.0)
    p, st = tuple(props.row()), (0.0,) * K.N_JS
    st = joint_friction(p, st, 1e-4, 0.0, 0.0)          # opens by 0.1 mm
    assert st[K.JS_SN] == 0.0 and st[K.JS_WP] == pytest.approx(1e-4)
    st = joint_friction(p, st, -0.6e-4, 1e-5, 0.0)      # closes part of the gap, slides: free
    assert st[K.JS_SN] == 0.0 and st[K.JS_T1] == 0.0
    st = joint_friction(p, st, -0.5e-4, 0.0, 0.0)       # 0.01 mm past closure
    assert st[K.JS_SN] == pytest.approx(-1e10 * 1e-5) and st[K.JS_WP] == 0.0
    st = joint_friction(p, st, 0.0, 1e-3, 0.0)          # slides at the friction limit
    assert st[K.JS_T1] == pytest.approx(1e5 * math.tan(math.radians(30.0)))
    st = joint_friction(p, st, 2e-5, 0.0, 0.0)          # lifts off again: free
    assert st[K.JS_SN] == 0.0 and st[K.JS_T1] == 0.0 and st[K.JS_WP] == pytest.approx(1e-5)


def test_rigid_column_under_gravity_has_joint_stress_rho_g_height_above():
    """A stack of 5 rigid blocks under gravity (declared) on a fixed base:
    each bed joint at height z carries sigma_n = -rho g (H - z) (1e-6),
    uniformly; without gravity declared nothing loads it."""
    for gravity in (True, False):
        m = Model()
        base = m.add_box([0, 0, -0.1], [0.2, 0.2, 0.0], (2, 2, 1), MAT, rigid=True)
        for k in range(5):
            m.add_box([0, 0, 0.1 * k], [0.2, 0.2, 0.1 * (k + 1)], (2, 2, 2), MAT, rigid=True)
        m.set_joints("friction", JointProps(kn=1e10, ks=1e10, phi=30.0))
        m.fix([base.node0])
        m.fix_rotation(base)
        if gravity:
            m.gravity = np.array([0.0, 0.0, -G])
        b = m.build()
        state = init(b, QS)
        pts = b.joint_points
        if not gravity:
            state, _, end = run(state, 1000, Stops(ratio_tol=1e-8))
            assert end.status == "converged"
            assert np.all(state.joints.state[:, K.JS_SN] == 0.0)
            continue
        state, _, end = run(state, 200_000, Stops(ratio_tol=1e-9))
        assert end.status == "converged"
        exact = -RHO * G * (0.5 - pts[:, 2])
        np.testing.assert_allclose(state.joints.state[:, K.JS_SN], exact, rtol=1e-6)


def test_rigid_and_very_stiff_deformable_blocks_give_the_same_joint_stresses():
    """One model, two block kinds: a block on a fixed one, an elastic joint
    (k_n = 1e10, k_s = 4e9 Pa/m), loaded by a pressure on half of its top
    face and a lateral pressure on one side (joint in compression,
    bending and shear).  Rigid blocks, and deformable ones 1e4 times
    stiffer than the joint over their height (E = 1e14 Pa), carry the same
    traction at every sub-contact: within 1e-3 of the largest traction
    (the deformable blocks' own compliance is of order 1e-4 of the
    joint's)."""
    def tractions(rigid):
        m = Model()
        mat = Elastic(E=1e14, nu=0.2, density=RHO)
        low = m.add_box([0, 0, 0], [0.2, 0.1, 0.05], (4, 2, 1), mat, rigid=rigid)
        up = m.add_box([0, 0, 0.05], [0.2, 0.1, 0.1], (4, 2, 1), mat, rigid=rigid)
        m.set_joints("elastic", JointProps(kn=1e10, ks=4e9))
        if rigid:
            m.fix([low.node0])
            m.fix_rotation(low)
        else:
            m.fix(np.arange(low.node0, low.node0 + low.n_nodes))
        m.add_pressure(2, 0.1, +1, ((0.0, 0.1), (0.0, 0.1)), 1e5)      # top face, x < 0.1 (plane axes: y, x)
        m.add_pressure(0, 0.0, -1, ((0.0, 0.1), (0.05, 0.1)), 2e4)     # the upper block's left face
        a = m.build()
        state, _, end = run(init(a, QS), 500_000, Stops(ratio_tol=1e-10))
        assert end.status == "converged"
        return state.joints.state[:, [K.JS_SN, K.JS_T1, K.JS_T2]].copy(), a.joint_points
    (t_r, p_r), (t_d, p_d) = tractions(True), tractions(False)
    np.testing.assert_array_equal(p_r, p_d)
    scale = np.abs(t_r).max()
    assert scale > 1e4
    np.testing.assert_allclose(t_d, t_r, rtol=0, atol=1e-3 * scale)
