"""Elastic cells computed as linear (elements.py, kernels.cells): the
10-tetrahedron cell as one matrix equals the zone kernel, the hexahedron
with incompatible modes is exact in pure bending, both are exact for
uniform strain, and a model of linear cells runs as one of zones.  Each
test states its formula and tolerance."""
import numpy as np
import pytest
from numba import njit

from masonrydem.dem import Elastic, Model
from masonrydem.dem.elements import cell_stiffness, elasticity
from masonrydem.dem.kernels import layout as L
from masonrydem.dem.kernels.zones import zone_forces
from masonrydem.dem import Numerics, init, max_rotation, prescribe
from masonrydem.dem.stops import Stops, run

# the quasi-static integration these tests were written at (local damping 0.8)
QS = Numerics(damping=0.8, safety=0.9)

pytestmark = pytest.mark.verification

SIZE = (0.12, 0.114, 0.075)
NU = 0.2
X = np.array([[c & 1, (c >> 1) & 1, (c >> 2) & 1] for c in range(8)], float) * SIZE


@njit
def _elastic_zones(nodes, zones, scratch):
    zone_forces(0, 1.0, nodes, zones, scratch)


def test_tet10_matrix_is_the_zone_kernel():
    """Column j of K (E = 1) is minus the zone kernel's nodal forces after
    one step of unit velocity of degree of freedom j from zero stress
    (dt = 1): the two agree to 1e-12 of the largest entry."""
    m = Model()
    m.add_box([0, 0, 0], SIZE, (1, 1, 1), Elastic(E=1.0, nu=NU))
    a = m.build()
    K = cell_stiffness("tet10", SIZE, NU)
    scratch = L.Scratch(np.zeros((5, 6)), np.zeros(5), np.zeros((10, 2), np.int64), np.zeros((3, 3)),
                        np.zeros((3, 3)), np.zeros((24, 0)), np.zeros((0, 24, 0)), np.zeros((4, 1)), np.zeros(1))
    probe = np.zeros((24, 24))
    for j in range(24):
        v = np.zeros((8, 3))
        v[j // 3, j % 3] = 1.0
        nodes = a.nodes._replace(v=v, f=np.zeros((8, 3)))
        _elastic_zones(nodes, a.zones._replace(stress=np.zeros((10, 6)), state=np.zeros((10, 3))), scratch)
        probe[:, j] = -nodes.f.ravel()
    np.testing.assert_allclose(K, probe, rtol=0, atol=1e-12 * np.abs(K).max())


def _energy(K, u, E=1.0):
    return 0.5 * E * u.ravel() @ K @ u.ravel()


@pytest.mark.parametrize("element", ["tet10", "hex8i"])
def test_uniform_strain_energy_is_exact(element):
    """Any uniform strain eps: nodal displacements eps x give the energy
    1/2 eps : D eps V (to 1e-12)."""
    rng = np.random.default_rng(3)
    e = rng.uniform(-1e-4, 1e-4, (3, 3))
    e = 0.5 * (e + e.T)
    u = X @ e.T
    voigt = np.array([e[0, 0], e[1, 1], e[2, 2], 2 * e[0, 1], 2 * e[1, 2], 2 * e[0, 2]])
    exact = 0.5 * voigt @ elasticity(NU) @ voigt * np.prod(SIZE)
    assert _energy(cell_stiffness(element, SIZE, NU), u) == pytest.approx(exact, rel=1e-12)


def test_hex8i_is_exact_in_pure_bending():
    """Pure bending about z, curvature k (the exact 3-D field:
    u_x = -k x y, u_y = k/2 (x^2 + nu (y^2 - z^2)), u_z = k nu y z, about
    the centre): one hex8i cell stores the beam's energy 1/2 E I k^2 L,
    I = b h^3 / 12, to 1e-10; the 10-tetrahedron cell, which locks in
    bending, at least 1.5 times it."""
    k = 1e-3
    x, y, z = (X - 0.5 * np.array(SIZE)).T
    u = np.column_stack([-k * x * y, 0.5 * k * (x * x + NU * (y * y - z * z)), k * NU * y * z])
    L_, h, b = SIZE
    exact = 0.5 * k * k * (b * h ** 3 / 12) * L_
    assert _energy(cell_stiffness("hex8i", SIZE, NU), u) == pytest.approx(exact, rel=1e-10)
    assert _energy(cell_stiffness("tet10", SIZE, NU), u) > 1.5 * exact


@pytest.mark.parametrize("element", ["tet10", "hex8i"])
def test_linear_cells_run_as_a_model(element):
    """A bar of 4 linear cells pulled by its end faces (the axial stiffness
    E A / L is exact for any cell that is exact in uniform strain): the
    reaction at equilibrium is E A u / L within 1e-6; a rigid rotation of
    the bar reads as such (max_rotation, to 1e-9 rad) and stores no
    force."""
    m = Model()
    E, Lb, a = 1e9, 0.4, 0.1
    m.add_box([0, 0, 0], [Lb, a, a], (4, 1, 1), Elastic(E=E, nu=0.0), element=element)
    left = m.select(lambda x: x[:, 0] < 1e-9)
    right = m.select(lambda x: x[:, 0] > Lb - 1e-9)
    m.fix(left)
    m.fix(right, dofs=[0], velocity=1e-7)
    m.add_monitor("pull", right, 0)
    state = init(m.build(), QS)
    assert state.zones.tets.shape[0] == 0 and state.assembly.cells.nodes.shape[0] == 4
    state, _, _ = run(state, 1000)
    state = prescribe(state, slice(None), 0.0)
    state, rec, end = run(state, 200_000, Stops(ratio_tol=1e-10))
    assert end.status == "converged"
    u = state.nodes.u[right, 0].mean()
    assert rec.last.force[0, 0] == pytest.approx(E * a * a * u / Lb, rel=1e-6)
    m2 = Model()
    m2.add_box([0, 0, 0], [Lb, a, a], (4, 1, 1), Elastic(E=E, nu=0.2), element=element)
    th = 1e-3
    for nd, x in enumerate(m2.x0):
        m2.fix([nd], velocity=np.cross([0.0, 0.0, th], x) / 10)
    state2 = init(m2.build(), QS)
    state2, _, _ = run(state2, 10)
    assert max_rotation(state2) == pytest.approx(th, abs=1e-9)
