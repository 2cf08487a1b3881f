"""Model assembly: joints found from geometry, sub-contact areas, bad input
refused before any computation, the divergence guard."""
import numpy as np
import pytest

from masonrydem.dem import Elastic, JointProps, Model, MohrCoulomb
from masonrydem.errors import InputError
from masonrydem.dem import kernels as K
from masonrydem.scene import build_scene
from masonrydem.dem import Controls, Numerics, init
from masonrydem.specimen.build import build
from masonrydem.dem.stops import Stops, run

# the quasi-static integration these tests were written at (local damping 0.8)
QS = Numerics(damping=0.8, safety=0.9)

WILLIS = "config/scenes/willis.yaml"

JP = JointProps(kn=1e11, ks=4e10, ft=0.3e6, c=0.36e6, phi=35.0, GI=9.0, GII=90.0)


@pytest.mark.parametrize("cells", [(7, 2, 2), (3, 1, 1), (5, 2, 3)])
def test_wallette_joints_and_areas(cells):
    """Running bond, 6 courses of 4 units: 18 head joints and 35 unit-to-unit
    bed contacts (course interfaces: 4 + 3 alternately), each a half-unit
    (120 mm) overlap.  Each contact's
    sub-contact areas sum to its overlap area exactly (1e-12), also where
    the meshes do not conform (3, 5 or 7 cells along a unit shifted by half a
    unit), and the total is 18 x 75 x 114 + 5 x 840 x 114 mm^2."""
    b = build(build_scene(WILLIS, settings={"physics.blocks": "elasto-plastic", "numerics.cells": list(cells),
                                            "numerics.subcontact_refine": 1})).assembly
    head = [c for c in b.contacts if c.axis == 0]
    bed = [c for c in b.contacts if c.axis == 2]
    assert len(head) == 18 and len(bed) == 35
    area = b.joints.area
    for c in b.contacts:
        assert area[c.sc].sum() == pytest.approx(c.area, rel=1e-12)
    for c in head:
        assert c.area == pytest.approx(0.075 * 0.114, rel=1e-12)
    assert {round(c.area / 0.114, 9) for c in bed} == {0.12}   # half-unit overlaps
    assert area.sum() == pytest.approx(18 * 0.075 * 0.114 + 5 * 0.84 * 0.114, rel=1e-12)
    w = b.joints.w
    cnt = b.joints.cnt
    for s in range(area.size):   # interpolation weights of each side sum to 1
        assert w[s, :cnt[s, 0]].sum() == pytest.approx(1.0, abs=1e-12)
        assert w[s, 4:4 + cnt[s, 1]].sum() == pytest.approx(1.0, abs=1e-12)


def _two_block_compression(cells_low, refine):
    """Two blocks under a uniform pressure p; the upper one has 4 x 2 x 2
    cells, the lower ``cells_low``.  Returns (max relative error of the
    sub-contacts' sigma_n, of the zones' sigma_zz) against -p."""
    m = Model()
    mat = Elastic(10e9, 0.2)
    m.add_box([0, 0, 0], [0.24, 0.1, 0.075], cells_low, mat)
    m.add_box([0, 0, 0.075], [0.24, 0.1, 0.15], (4, 2, 2), mat)
    m.set_joints("elastic", JointProps(kn=1e11, ks=4e10), refine=refine)
    base = m.select(lambda x: x[:, 2] < 1e-9)
    m.fix(base, dofs=[2])
    x = m.x0
    m.fix(base[np.argmin(np.linalg.norm(x[base], axis=1))], dofs=[0, 1])
    m.fix(base[np.argmin(np.linalg.norm(x[base] - [0.24, 0, 0], axis=1))], dofs=[1])
    p = 0.4e6
    m.add_pressure(2, 0.15, +1, ((-1, 1), (-1, 1)), p)
    state = init(m.build(), QS)
    state, _, end = run(state, 300_000, Stops(ratio_tol=1e-11))
    assert end.status == "converged"
    return np.abs(state.joints.state[:, K.JS_SN] / -p - 1).max(), np.abs(state.zones.stress[:, 2] / -p - 1).max()


def test_conforming_joint_transmits_uniform_compression_exactly():
    """Matching face meshes: every sub-contact carries sigma_n = -p and every
    zone sigma_zz = -p (relative 1e-8): the joint passes the patch test."""
    assert max(_two_block_compression((4, 2, 2), 1)) < 1e-8


def test_non_conforming_joint_transmits_uniform_compression_exactly():
    """Non-matching face meshes (3 x 1 x 1 below 4 x 2 x 2): the
    sub-contacts are the points of a rule on the union of both face grids,
    exact for both sides' bilinear fields, so uniform compression is
    reproduced exactly too (relative 1e-8; points on one face's gridpoints
    alone, as before, erred by 3.1 %)."""
    assert max(_two_block_compression((3, 1, 1), 1)) < 1e-8


# --- bad input is refused, naming the field ----------------------------------------------
@pytest.mark.parametrize("make, field", [
    (lambda m: m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 1, Elastic(-1.0, 0.2)), "blocks[0].material.E"),
    (lambda m: m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 1, Elastic(1e9, 0.5)), "blocks[0].material.nu"),
    (lambda m: m.add_box([0, 0, 0], [0.1, 0.0, 0.1], 1, Elastic(1e9, 0.2)), "blocks[0].size"),
    (lambda m: m.add_box([0, 0, 0], [0.1, 0.1, 0.1], (2, 0, 1), Elastic(1e9, 0.2)), "blocks[0].cells"),
    (lambda m: m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 1,
                         MohrCoulomb(1e9, 0.2, ft=0.0, c=1e6, phi=30, Gf=50)), "blocks[0].material.ft"),
    (lambda m: m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 1,
                         MohrCoulomb(1e9, 0.2, ft=1e6, c=1e6, phi=95, Gf=50)), "blocks[0].material.phi"),
    (lambda m: m.set_joints("mohr_coulombish", JP), "joints.law"),
    (lambda m: m.add_tet_block([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2, 3]],
                               Elastic(1e9, 0.2)).mesh and m.build(), "blocks[0].mesh"),
])
def test_bad_input_refused(make, field):
    m = Model()
    with pytest.raises(InputError) as e:
        make(m)
    assert e.value.field == field
    assert field in str(e.value)


@pytest.mark.parametrize("props, field", [
    (JointProps(kn=0.0, ks=1e10, ft=1e5, c=1e5, phi=30, GI=5, GII=50), "kn"),
    (JointProps(kn=1e10, ks=1e10, ft=-1.0, c=1e5, phi=30, GI=5, GII=50), "ft"),
    (JointProps(kn=1e10, ks=1e10, ft=1e5, c=1e5, phi=30, GI=0.0, GII=50), "GI"),
])
def test_bad_joint_refused_at_build(props, field):
    m = Model()
    m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 1, Elastic(1e9, 0.2))
    m.add_box([0, 0, 0.1], [0.1, 0.1, 0.2], 1, Elastic(1e9, 0.2))
    m.set_joints("coupled_softening", props)
    with pytest.raises(InputError, match=rf"joints\[0\].*\.{field}"):
        init(m.build(), QS)


def _dynamic_block():
    m = Model()
    m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 2, Elastic(1e9, 0.2, density=2000.0))
    m.fix(m.select(lambda x: x[:, 2] < 1e-9))
    return m


def test_time_step_above_critical_refused():
    """dt above the critical step 2 min sqrt(m/k) is refused at set-up;
    0.9 of it is accepted."""
    crit = init(_dynamic_block().build(), Numerics(mode="dynamic", safety=0.9)).integrator.dt_crit
    with pytest.raises(InputError, match="solver.dt"):
        init(_dynamic_block().build(), Numerics(mode="dynamic", dt=1.01 * crit, safety=0.9))
    assert init(_dynamic_block().build(), Numerics(mode="dynamic", dt=0.9 * crit, safety=0.9)).integrator.dt == 0.9 * crit


def test_divergence_guard_names_the_node():
    """A run forced beyond the stability limit (dt set to 3 x critical after
    set-up, bypassing the check) grows exponentially; the guard stops it
    with status 'diverged' and names a node, not a silent number."""
    m = _dynamic_block()
    top = m.select(lambda x: x[:, 2] > 0.1 - 1e-9)
    m.add_force(top, [0, 0, -100.0])
    state = init(m.build(), Numerics(mode="dynamic", safety=0.9))
    state = state._replace(integrator=state.integrator._replace(dt=3.0 * state.integrator.dt_crit))
    state, _, res = run(state, 100_000)
    assert res.status == "diverged"
    assert "node" in res.message and "block 0" in res.message
    assert res.steps < 100_000


def test_velocity_ramp_displacement():
    """A prescribed velocity v ramped over N steps moves a node by
    v sum_k min(1, k/N) = v (T - N + (N + 1)/2) after T >= N steps
    (exact up to roundoff), and by v T when not ramped."""
    m = _dynamic_block()
    top = m.select(lambda x: x[:, 2] > 0.1 - 1e-9)
    m.fix(top, dofs=[2], velocity=1e-6)
    state = init(m.build(), QS)
    N, T = 300, 1000
    state, _, _ = run(state, T, controls=Controls(ramp_steps=N))
    assert state.nodes.u[top, 2] == pytest.approx(1e-6 * (T - N + (N + 1) / 2), rel=1e-12)
    state, _, _ = run(state, T)
    assert state.nodes.u[top, 2] == pytest.approx(1e-6 * (2 * T - N + (N + 1) / 2), rel=1e-12)


def test_large_rotation_stops_the_run():
    """The formulation is small-displacement: a block spun rigidly (v = omega
    x r on every node) past the rotation limit stops with status
    'large_displacement', at an angle between the limit and the limit plus
    the rotation of one check interval (20 chunks)."""
    m = Model()
    m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 1, Elastic(1e9, 0.2))
    x = m.x0
    omega = 1e-4          # rad per step, about z
    vel = omega * np.column_stack([-(x[:, 1] - 0.05), x[:, 0] - 0.05, 0 * x[:, 0]])
    for nd in range(x.shape[0]):
        m.fix([nd], dofs=(0, 1, 2), velocity=vel[nd])
    state = init(m.build(), Numerics(rotation_limit=0.05, damping=0.8, safety=0.9))
    state, _, res = run(state, 100_000, chunk=10)
    assert res.status == "large_displacement"
    assert 0.05 < omega * res.steps <= 0.05 + omega * 200 + 1e-12


def test_strip_node_numbered_after_all_blocks():
    """A strip added before a block still gets its own node, after every
    block node; its sub-contacts and monitor point at that node."""
    m = Model()
    m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 1, Elastic(1e9, 0.2))
    strip = m.add_strip("s", 2, 0.1, +1, ((0, 0.1), (0, 0.1)), kn=1e10)
    m.add_box([0.2, 0, 0], [0.3, 0.1, 0.1], 1, Elastic(1e9, 0.2))
    m.add_monitor("s", [strip], 2)
    b = m.build()
    assert b.strip_nodes[strip.index] == 16 and b.n == 17
    assert np.all(b.bearings.nodes[:, 4] == 16)
    assert b.monitors.nodes.tolist() == [16]
    assert np.all(b.nodes.fixed[16] == 1) and np.all(b.nodes.fixed[8] == 0)


def test_refused_strip_leaves_nothing_behind():
    """A strip refused for a bad velocity adds no sub-contact."""
    m = Model()
    m.add_box([0, 0, 0], [0.1, 0.1, 0.1], 1, Elastic(1e9, 0.2))
    with pytest.raises(InputError, match="strips.s.velocity"):
        m.add_strip("s", 2, 0.1, +1, ((0, 0.1), (0, 0.1)), kn=1e10, velocity=(0, 1))
    assert m.build().bearings.area.size == 0 and m.strips == []


def test_joint_forces_gathered_per_node_add_what_a_scatter_adds():
    """Each node gathers the forces of its sub-contacts (contacts.with_gather)
    in sub-contact order: the sums are those of a loop that scatters each
    sub-contact's force to its nodes (+w on side A, -w on side B), bit for
    bit, on a wallette whose faces do not match node for node; in each of
    eight lanes of a batch (force row s S + b: sub-contact s of lane b), as
    a run alone."""
    from numba import njit

    from masonrydem.dem.kernels.lanes import gather_forces
    sc = build(build_scene(WILLIS, settings={"physics.blocks": "elasto-plastic", "numerics.cells": [5, 2, 3],
                                             "numerics.subcontact_refine": 1})).assembly.joints
    rng = np.random.default_rng(1)
    lanes, n = 8, sc.area.size
    force = np.asfortranarray(rng.standard_normal((n * lanes, 3)))
    f0 = rng.standard_normal((sc.gptr.size - 1, 3, lanes))
    want = f0.copy()
    for b in range(lanes):
        for s in range(n):
            for k in range(sc.cnt[s, 0]):
                want[sc.nodes[s, k], :, b] += sc.w[s, k] * force[s * lanes + b]
            for k in range(4, 4 + sc.cnt[s, 1]):
                want[sc.nodes[s, k], :, b] -= sc.w[s, k] * force[s * lanes + b]
    got = f0.copy()
    w = force.T
    njit(lambda f, a, b, c, x, y, z: gather_forces(f.ravel(), a, b, c, x, y, z, 8))(got, sc.gptr, sc.gs, sc.gw,
                                                                                      w[0], w[1], w[2])
    assert np.array_equal(got, want)
