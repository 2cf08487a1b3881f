"""Closed-form verification of the solver (docs/formulation.md, 13).

Each test states its formula and tolerance.  Run only these with
``pytest -m verification``.
"""
import math

import numpy as np
import pytest
from scipy.spatial import Delaunay

from masonrydem.dem import Elastic, JointProps, Model, MohrCoulomb
from masonrydem.dem import kernels as K
from masonrydem.dem import Numerics, init, prescribe
from masonrydem.dem.stops import Stops, run
from specimens import block_nodes, pull_joint, shear_joint, work

# the quasi-static integration these tests were written at (local damping 0.8)
QS = Numerics(damping=0.8, safety=0.9)

pytestmark = pytest.mark.verification

JOINT = JointProps(kn=1e11, ks=4e10, ft=0.3e6, c=0.36e6, phi=35.0, GI=9.0, GII=90.0)
TAN35 = math.tan(math.radians(35.0))


def _hooke(E, nu, eps):
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    return lam * np.trace(eps) * np.eye(3) + 2 * mu * eps


def _as_tensor(s):
    return np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])


# --- patch test and rigid-body motion ---------------------------------------------
def _unstructured_block(seed=1):
    rng = np.random.default_rng(seed)
    corners = np.array([[x, y, z] for x in (0, 0.2) for y in (0, 0.1) for z in (0, 0.15)])
    pts = np.vstack([corners, rng.uniform([0, 0, 0], [0.2, 0.1, 0.15], size=(40, 3))])
    return pts, Delaunay(pts).simplices


def test_patch_test_unstructured():
    """Patch test: the boundary nodes of an unstructured tetrahedral block
    follow the linear field u = eps x; after the quasi-static solution every
    interior node satisfies u = eps x and every zone carries
    sigma = lambda tr(eps) I + 2 mu eps (relative error < 1e-6)."""
    pts, tets = _unstructured_block()
    m = Model()
    E, nu = 20e9, 0.25
    m.add_tet_block(pts, tets, Elastic(E, nu))
    eps = np.array([[2e-4, 3e-5, -1e-5], [3e-5, -1e-4, 4e-5], [-1e-5, 4e-5, 5e-5]])
    x = m.x0
    on_boundary = np.any(np.isclose(x, 0) | np.isclose(x, [0.2, 0.1, 0.15]), axis=1)
    bnd = np.flatnonzero(on_boundary)
    steps = 100
    for nd in bnd:      # reach u = eps x in `steps` steps at constant velocity
        m.fix([nd], dofs=(0, 1, 2), velocity=eps @ x[nd] / steps)
    state = init(m.build(), QS)
    state, _, _ = run(state, steps)
    state = prescribe(state, slice(None), 0.0)
    state, _, res = run(state, 200_000, Stops(ratio_tol=1e-12))
    assert res.status == "converged"
    inner = np.flatnonzero(~on_boundary)
    assert inner.size > 10
    np.testing.assert_allclose(state.nodes.u[inner], x[inner] @ eps.T, rtol=0, atol=1e-6 * np.abs(eps).max() * 0.2)
    sig = _hooke(E, nu, eps)
    for st in state.zones.stress:
        np.testing.assert_allclose(_as_tensor(st), sig, rtol=0, atol=1e-6 * np.abs(sig).max())


def test_patch_test_mixed_discretization():
    """The same patch test on a structured box of hexahedral cells with the
    two-overlay mixed discretization: sigma = lambda tr(eps) I + 2 mu eps in
    every zone (relative error < 1e-6)."""
    m = Model()
    E, nu = 20e9, 0.3
    blk = m.add_box([0, 0, 0], [0.3, 0.1, 0.2], (3, 2, 2), Elastic(E, nu))
    eps = np.array([[-1e-4, 2e-5, 0], [2e-5, 3e-5, 1e-5], [0, 1e-5, 2e-4]])
    x = m.x0
    bnd = np.flatnonzero(np.any(np.isclose(x, 0) | np.isclose(x, [0.3, 0.1, 0.2]), axis=1))
    for nd in bnd:
        m.fix([nd], dofs=(0, 1, 2), velocity=eps @ x[nd] / 50)
    state = init(m.build(), QS)
    state, _, _ = run(state, 50)
    state = prescribe(state, slice(None), 0.0)
    state, _, end = run(state, 200_000, Stops(ratio_tol=1e-12))
    assert end.status == "converged"
    sig = _hooke(E, nu, eps)
    for st in state.zones.stress:
        np.testing.assert_allclose(_as_tensor(st), sig, rtol=0, atol=1e-6 * np.abs(sig).max())
    assert blk.n_nodes == 4 * 3 * 3


@pytest.mark.parametrize("motion", ["translation", "rotation"])
def test_rigid_body_motion_no_stress(motion):
    """Rigid-body motion creates no strain: a translation of any size, and a
    rotation rate v = omega x (x - c) whose velocity gradient is skew, give
    de = dt sym(grad v) = 0, so the stresses stay zero (|sigma| < 1e-6 Pa
    against an elastic scale E * |v| dt / h of about 1e3 Pa)."""
    pts, tets = _unstructured_block(seed=3)
    m = Model()
    m.add_tet_block(pts, tets, Elastic(20e9, 0.2))
    x = m.x0
    if motion == "translation":
        vel = np.tile([1e-3, -2e-3, 5e-4], (x.shape[0], 1))
    else:
        omega = np.array([1e-4, -2e-4, 3e-4])
        vel = np.cross(omega, x - x.mean(axis=0))
    for nd in range(x.shape[0]):
        m.fix([nd], dofs=(0, 1, 2), velocity=vel[nd])
    state = init(m.build(), QS)
    state, _, _ = run(state, 1 if motion == "rotation" else 1000)
    assert np.abs(state.zones.stress).max() < 1e-6


# --- elastic stack and cantilever ------------------------------------------------------
def test_elastic_stack_axial():
    """A stack of 5 blocks (height h each, 4 joints) under an axial pressure
    sigma on a frictionless base: delta = sigma (H/E + n_joints/k_n).  The
    uniaxial stress state has linear displacements, which the zones and the
    joints represent exactly, so the only error is the relaxation's: at an
    unbalanced-force ratio of 1e-8 the mean top displacement is within
    5e-10 of the closed form and every top node within 2e-8 of it
    (measured; allowed 1e-8 and 1e-7: a 0.1 % error in a joint's stiffness
    would be caught 10,000 times over)."""
    m = Model()
    E, h, sigma, kn = 10e9, 0.075, 0.5e6, 5e10
    for k in range(5):
        m.add_box([0, 0, k * h], [0.24, 0.114, (k + 1) * h], (2, 1, 1), Elastic(E, 0.2))
    m.set_joints("elastic", JointProps(kn=kn, ks=0.4 * kn))
    x = m.x0
    base = m.select(lambda x: x[:, 2] < 1e-9)
    m.fix(base, dofs=[2])
    m.fix(base[np.argmin(np.linalg.norm(x[base], axis=1))], dofs=[0, 1])
    m.fix(base[np.argmin(np.linalg.norm(x[base] - [0.24, 0, 0], axis=1))], dofs=[1])
    H = 5 * h
    m.add_pressure(2, H, +1, ((-1, 1), (-1, 1)), sigma)
    top = m.select(lambda x: x[:, 2] > H - 1e-9)
    m.add_monitor("top", top, 2)
    state = init(m.build(), QS)
    state, _, res = run(state, 500_000, Stops(ratio_tol=1e-8))
    assert res.status == "converged"
    expected = sigma * (H / E + 4 / kn)
    assert -state.nodes.u[top, 2].mean() == pytest.approx(expected, rel=1e-8)
    np.testing.assert_allclose(-state.nodes.u[top, 2], expected, rtol=1e-7)


def test_cantilever_of_blocks():
    """A cantilever of 4 blocks (length a each, section b x d, joints with
    k_n, k_s) clamped at x = 0 with a tip load P.  Timoshenko beam plus
    joint compliance:
        delta = P L^3/(3 E I) + P L/(kappa G A)
                + sum_j P (L - x_j)^2 / (k_n I) + n_j P / (k_s A),
    I = b d^3 / 12, kappa = 5/6.
    Constant-strain tetrahedra are stiff in bending, and gridpoint
    sub-contacts integrate the joint's second moment by the trapezoid rule
    (12.5 % too stiff with 4 cells through the depth), so the solver
    converges to the formula from below.  Measured on 4x1x2, 8x2x4 and
    16x4x8 cells per block: 0.765, 0.919, 0.975 of the formula.  Asserted:
    the error falls at every refinement with an observed order above 1, and
    the Richardson extrapolation of the three meshes (with the observed
    order) agrees with the formula within 3 %."""
    def deflection(cells):
        m = Model()
        E, nu, a, b, d = 20e9, 0.2, 0.25, 0.1, 0.1
        kn = 2e11
        for j in range(4):
            m.add_box([j * a, 0, 0], [(j + 1) * a, b, d], cells, Elastic(E, nu))
        m.set_joints("elastic", JointProps(kn=kn, ks=0.4 * kn))
        m.fix(m.select(lambda x: x[:, 0] < 1e-9))
        L = 4 * a
        tip = m.select(lambda x: x[:, 0] > L - 1e-9)
        P = 1000.0
        m.add_force(tip, [0, 0, -P / tip.size])
        state = init(m.build(), QS)
        state, _, end = run(state, 3_000_000, Stops(ratio_tol=1e-7), chunk=1000)
        assert end.status == "converged"
        I, A, G = b * d ** 3 / 12, b * d, E / (2 * (1 + nu))
        xj = np.array([a, 2 * a, 3 * a])
        exact = (P * L ** 3 / (3 * E * I) + P * L / (5 / 6 * G * A)
                 + np.sum(P * (L - xj) ** 2 / (kn * I)) + 3 * P / (0.4 * kn * A))
        return -state.nodes.u[tip, 2].mean() / exact
    r1, r2, r3 = (deflection(c) for c in ((4, 1, 2), (8, 2, 4), (16, 4, 8)))
    assert abs(r3 - 1) < abs(r2 - 1) < abs(r1 - 1)
    q = (r2 - r1) / (r3 - r2)
    order = math.log2(q)
    assert order > 1.0
    extrapolated = r3 + (r3 - r2) / (q - 1)
    assert extrapolated == pytest.approx(1.0, abs=0.03)


# --- joints ---------------------------------------------------------------------------
def test_joint_tension_peak_and_fracture_energy():
    """A joint pulled apart: sigma = k_n u up to f_t, then linear softening
    to zero at w_u = 2 G_I / f_t.  Peak f_t A and dissipated energy
    G_I A (the work of the pull once the joint carries nothing) within 2 %;
    the initial slope is k_n A (1 %, the blocks being 1e4 times stiffer)."""
    state, H, A = pull_joint(JOINT)
    P, u = H.force[:, 0], H.disp[:, 0]
    assert P.max() == pytest.approx(JOINT.ft * A, rel=0.02)
    assert abs(P[-1]) < 1e-6 * P.max()
    assert work(H) == pytest.approx(JOINT.GI * A, rel=0.02)
    early = (P > 0.1 * P.max()) & (P < 0.6 * P.max()) & (u < JOINT.ft / JOINT.kn)
    slope = np.polyfit(u[early], P[early], 1)[0]
    assert slope == pytest.approx(JOINT.kn * A, rel=0.01)
    assert np.all(state.joints.state[:, K.JS_D] == 1.0)


@pytest.mark.parametrize("sigma", [0.0, 0.2e6])
def test_joint_shear_peak_residual_energy(sigma):
    """A joint sheared at constant compressive normal stress sigma: peak
    c + sigma tan(phi), residual sigma tan(phi) (2 %); the work of the shear
    load is G_II A + sigma tan(phi) s_p A + tau_res^2/(2 k_s) A (friction
    work on the plastic slip s_p, and the elastic energy still stored),
    within 2 %; at sigma = 0 that is G_II A."""
    state, H, A = shear_joint(JOINT, sigma, rate=1e-8)
    P = H.force[:, 0]
    assert P.max() == pytest.approx((JOINT.c + sigma * TAN35) * A, rel=0.02)
    tau_res = sigma * TAN35
    assert P[-1] == pytest.approx(tau_res * A, rel=0.02, abs=1e-3 * JOINT.c * A)
    sp = state.joints.state[:, K.JS_SP].mean()
    expected = (JOINT.GII + tau_res * sp + tau_res ** 2 / (2 * JOINT.ks)) * A
    assert work(H) == pytest.approx(expected, rel=0.02)


def _incline(psi_deg, mode, phi=30.0):
    """A block resting on a fixed block, gravity tilted by psi about y (an
    incline of slope psi), joint with friction only (c = f_t = 0)."""
    m = Model()
    mat = Elastic(E=1e9, nu=0.2, density=2000.0)
    base = m.add_box([0, 0, 0], [0.4, 0.2, 0.1], (2, 1, 1), mat)
    blk = m.add_box([0.1, 0.05, 0.1], [0.2, 0.15, 0.15], (1, 1, 1), mat)
    m.set_joints("coupled_softening", JointProps(kn=1e10, ks=1e10, phi=phi))
    m.fix(block_nodes(m, base))
    psi = math.radians(psi_deg)
    m.gravity = 9.81 * np.array([math.sin(psi), 0.0, -math.cos(psi)])
    m.add_monitor("block", block_nodes(m, blk), 0)
    return m, blk


@pytest.mark.parametrize("psi", [29.0, 31.0])
def test_block_on_incline_rests_just_below_phi_and_slides_just_above(psi):
    """phi = 30 deg, the threshold bracketed within a degree: at 29 deg the
    block comes to rest (ratio < 1e-6, a sliding block never would) with a
    mean slide along the slope of the order of the elastic shear estimate
    W sin(psi) / (k_s A) (below 4 times it: local slip at the lightly
    loaded uphill edge, the tilted weight's overturning moment, is
    allowed); at 31 deg it never comes to rest and slides on (over 1000
    times the estimate in 200,000 steps)."""
    m, blk = _incline(psi, "static")
    state = init(m.build(), QS)
    state, _, end = run(state, 200_000, Stops(ratio_tol=1e-6))
    weight = 2000.0 * 0.1 * 0.1 * 0.05 * 9.81
    elastic = weight * math.sin(math.radians(psi)) / (1e10 * 0.01)
    slide = abs(state.nodes.u[block_nodes(m, blk), 0].mean()) / elastic
    if psi < 30.0:
        assert end.status == "converged" and slide < 4.0
    else:
        assert end.status == "max_steps" and slide > 1000.0


def test_block_on_incline_slides_above_phi():
    """Slope 40 deg > phi = 30 deg, dynamic, undamped: the block slides with
    a = g (sin psi - cos psi tan phi) (within 2 %, from a quadratic fit of its
    mean displacement over 0.1 s)."""
    psi, phi = 40.0, 30.0
    m, blk = _incline(psi, "dynamic", phi)
    state = init(m.build(), Numerics(mode="dynamic", safety=0.5))
    nsteps = int(0.1 / state.integrator.dt)
    state, rec, _ = run(state, nsteps)
    H = rec.history
    t = H.step * state.integrator.dt
    u = H.disp[:, 0]
    acc = 2 * np.polyfit(t, u, 2)[0]
    exact = 9.81 * (math.sin(math.radians(psi)) - math.cos(math.radians(psi)) * math.tan(math.radians(phi)))
    assert acc == pytest.approx(exact, rel=0.02)


# --- zones: crack band ---------------------------------------------------------------
def _zone_bar(nx, rate=2e-9):
    """A bar 0.1 x 0.02 x 0.02 m of Mohr-Coulomb material pulled along x
    under displacement control; the cells of the middle (the one containing
    x = 0.05 + h/2) are 2 % weaker so that the crack localises there."""
    L, a = 0.1, 0.02
    mat = MohrCoulomb(E=15e9, nu=0.2, ft=2e6, c=3e6, phi=35.0, Gf=100.0)
    m = Model()
    m.add_box([0, 0, 0], [L, a, a], (nx, 1, 1), mat)
    left = m.select(lambda x: x[:, 0] < 1e-9)
    right = m.select(lambda x: x[:, 0] > L - 1e-9)
    m.fix(left, dofs=[0])
    m.fix(left[:1], dofs=[1, 2])
    m.fix(right, dofs=[0], velocity=rate)
    m.add_monitor("pull", right, 0)
    b = m.build()
    centroid = b.nodes.x0[b.zones.tets].mean(axis=1)[:, 0]
    h = L / nx
    weak = np.abs(centroid - (0.5 * L + 0.5 * h) + 1e-12) < 0.5 * h
    b.zones.par[weak, K.ZP_FT] *= 0.98
    state = init(b, QS)
    wu = 2 * mat.Gf / mat.ft
    state, rec, _ = run(state, 2_000_000, Stops(disp_limit=1.3 * wu, monitor="pull"), record_every=1)
    return state, rec.history, a * a


def test_zone_bar_crack_band_energy_mesh_independent():
    """A zone bar in tension: peak 0.98 f_t A (2 %) and dissipated energy
    G_f A independent of the mesh: within 5 % on 5, 10 and 20 cells along
    the bar (the crack band h = cell length along the crack normal)."""
    energies = []
    for nx in (5, 10, 20):
        state, H, A = _zone_bar(nx)
        P = H.force[:, 0]
        assert P.max() == pytest.approx(0.98 * 2e6 * A, rel=0.02)
        assert abs(P[-1]) < 0.01 * P.max()
        energies.append(work(H))
    np.testing.assert_allclose(energies, 100.0 * A, rtol=0.05)


# --- quasi-static rate independence ---------------------------------------------------
def test_quasi_static_rate_independence():
    """Halving the loading rate of the softening zone bar (10 cells) changes
    the peak and the dissipated energy by less than 1 %."""
    _, H1, _ = _zone_bar(10, rate=4e-9)
    _, H2, _ = _zone_bar(10, rate=2e-9)
    assert H1.force[:, 0].max() == pytest.approx(H2.force[:, 0].max(), rel=0.01)
    assert work(H1) == pytest.approx(work(H2), rel=0.01)


def test_brittle_coulomb_joint():
    """Brittle Coulomb with tension cut-off: a joint pulled apart carries
    k_n u up to f_t A (2 %), then nothing: the work of the pull is only the
    elastic energy f_t^2 / (2 k_n) A (5 %), far below G_I A of the softening
    law; sheared at zero normal stress it loses its cohesion at once."""
    state, H, A = pull_joint(JOINT, law="brittle_coulomb")
    assert H.force[:, 0].max() == pytest.approx(JOINT.ft * A, rel=0.02)
    assert abs(H.force[-1, 0]) < 1e-9 * JOINT.ft * A
    assert work(H) == pytest.approx(JOINT.ft ** 2 / (2 * JOINT.kn) * A, rel=0.05)
    state, H, A = shear_joint(JOINT, 0.0, rate=1e-8, law="brittle_coulomb", travel=1e-4)
    assert H.force[:, 0].max() == pytest.approx(JOINT.c * A, rel=0.02)
    assert abs(H.force[-1, 0]) < 1e-9 * JOINT.c * A


# --- gravity -------------------------------------------------------------------------
def test_column_under_gravity_has_stress_rho_g_height_above():
    """An elastic column (0.1 x 0.1 x 1 m, 10 cells high) under gravity
    (declared) on a roller base: uniaxial sigma_zz = -rho g (H - z) at the
    centroid of each cell (the exact field is linear; constant-strain
    tetrahedra carry its cell mean), within 1 % of rho g H; sigma_xx and
    sigma_yy vanish (below 1 % of rho g H)."""
    rho, g, H = 2000.0, 9.81, 1.0
    m = Model()
    m.add_box([0, 0, 0], [0.1, 0.1, H], (1, 1, 10), Elastic(E=1e9, nu=0.2, density=rho))
    base = m.select(lambda x: x[:, 2] < 1e-9)
    m.fix(base, dofs=[2])
    m.fix(base[:1], dofs=[0, 1])
    m.fix(base[1:2], dofs=[1])
    m.gravity = np.array([0.0, 0.0, -g])
    b = m.build()
    state = init(b, QS)
    state, _, end = run(state, 400_000, Stops(ratio_tol=1e-7))
    assert end.status == "converged"
    zc = b.nodes.x0[b.zones.tets].mean(axis=1)[:, 2]
    cell = np.floor(zc / 0.1).astype(int)
    w = b.zones.vol * b.zones.wt
    for c in range(10):
        sel = cell == c
        szz = np.sum(state.zones.stress[sel, 2] * w[sel]) / np.sum(w[sel])
        assert szz == pytest.approx(-rho * g * (H - 0.1 * (c + 0.5)), abs=0.01 * rho * g * H)
        for d in (0, 1):
            assert abs(np.sum(state.zones.stress[sel, d] * w[sel]) / np.sum(w[sel])) < 0.01 * rho * g * H


def test_elastic_blocks_never_evaluate_a_yield_function():
    """The kernel is specialised on the model's zone law: an elastic model
    runs without any yield check.  Shown by giving its zones a tensile
    strength of 1 Pa (which an elastic law ignores) and pulling a bar to
    1e5 times that stress: it stays linear with no plastic strain; the same
    rows under the Mohr-Coulomb law crack."""
    results = {}
    for law in (K.ZONE_ELASTIC, K.ZONE_MOHR_COULOMB):
        m = Model()
        m.add_box([0, 0, 0], [0.1, 0.02, 0.02], (4, 1, 1), Elastic(E=1e9, nu=0.0))
        left = m.select(lambda x: x[:, 0] < 1e-9)
        right = m.select(lambda x: x[:, 0] > 0.1 - 1e-9)
        m.fix(left, dofs=[0])
        m.fix(left[:1], dofs=[1, 2])
        m.fix(right, dofs=[0], velocity=1e-8)
        b = m.build()
        b.zlaw = law
        b.zones.par[:, K.ZP_FT] = 1.0
        b.zones.par[:, K.ZP_C] = 1e9
        b.zones.par[:, K.ZP_GF] = 1.0
        state = init(b, QS)
        state, _, _ = run(state, 1000)
        results[law] = (state.zones.stress[:, 0].mean(), state.zones.state[:, K.ZS_EPT].max())
    sxx, ept = results[K.ZONE_ELASTIC]
    assert sxx == pytest.approx(1e9 * 1e-5 / 0.1, rel=0.05) and ept == 0.0
    assert results[K.ZONE_MOHR_COULOMB][1] > 0.0


def test_without_gravity_the_kernel_never_reads_the_gravity_masses():
    """The kernel is specialised on whether the model has gravity: without
    it, the masses that gravity would load (``mphys``) are never read.
    Shown by poisoning them with NaN: a model without gravity runs exactly
    as with finite masses (a computed m g with g = 0 would give NaN * 0 =
    NaN everywhere); the same model with gravity declared turns
    non-finite."""
    def bar(gravity, poison):
        m = Model()
        m.add_box([0, 0, 0], [0.1, 0.02, 0.02], (4, 1, 1), Elastic(E=1e9, nu=0.2, density=2000.0))
        left = m.select(lambda x: x[:, 0] < 1e-9)
        m.fix(left)
        m.fix(m.select(lambda x: x[:, 0] > 0.1 - 1e-9), dofs=[0], velocity=1e-8)
        m.gravity = np.array(gravity)
        b = m.build()
        if poison:
            b.nodes.mgrav[:] = np.nan
        state = init(b, QS)
        state, _, _ = run(state, 500)
        return state
    clean, poisoned = bar([0.0, 0.0, 0.0], False), bar([0.0, 0.0, 0.0], True)
    assert np.isfinite(poisoned.nodes.u).all() and np.array_equal(clean.nodes.u, poisoned.nodes.u)
    assert not np.isfinite(bar([0.0, 0.0, -9.81], True).nodes.u).all()
