"""Stability bounds as pure functions: Gershgorin bounds of the nodal
stiffness (zones, sub-contacts, rigid bodies), the masses that make a
step stable, and the critical step.

Each component of a node (x, y, z) has its own bound, the absolute row
sum of its row of the stiffness matrix (summed over the elements at the
node), and so its own scaled mass: Gershgorin's theorem bounds the
eigenvalues of M^-1 K by the largest row sum of |K| / m row by row, so a
per-component mass is as stable as one per node, and lighter in a node's
softer directions (Underwood's dynamic relaxation scales each degree of
freedom so).  Rigid bodies keep one isotropic bound (their rows turn with
them).

The critical step counts the damping: local damping multiplies a force
that opposes the velocity by (1 + alpha), and in the highest mode (the
displacements alternate in sign every step) every force opposes the
velocity, so central differences are stable for
dt < dt_crit = 2 min sqrt(m_i / ((1 + alpha) k_i)), with k_i a Gershgorin
bound of the nodal stiffness: exactly the limit for one degree of freedom
(tests/test_stability.py), and conservative otherwise.  Without the
(1 + alpha) the usual criterion 2 sqrt(m / k) lets alpha = 0.8 runs
diverge from 0.75 of that step.
"""
import math

import numpy as np

from . import kernels as K
from ..errors import InputError

QUASI_STATIC = "quasi-static"
DYNAMIC = "dynamic"


def zone_stiffness(stiff, tets, dn, wvol, zp, chunk=20000):
    """Adds, per node and component (stiff (n, 3)), a Gershgorin bound of the
    zones' stiffness: the absolute row sum of the element matrices
    w V B^T D B, summed over the node's tetrahedra.  Mixed discretization
    only lowers the stiffness (it averages the volumetric strain), so this
    bounds the mixed stiffness too: omega_max^2 <= max_i k_i / m_i."""
    for s in range(0, tets.shape[0], chunk):
        t = tets[s:s + chunk]
        g = dn[s:s + chunk].reshape(-1, 3, 3)
        grads = np.concatenate([-g.sum(axis=1, keepdims=True), g], axis=1)  # (n, 4, 3)
        n = t.shape[0]
        B = np.zeros((n, 6, 12))
        for a in range(4):
            gx, gy, gz = grads[:, a, 0], grads[:, a, 1], grads[:, a, 2]
            c = 3 * a
            B[:, 0, c], B[:, 1, c + 1], B[:, 2, c + 2] = gx, gy, gz
            B[:, 3, c], B[:, 3, c + 1] = gy, gx
            B[:, 4, c + 1], B[:, 4, c + 2] = gz, gy
            B[:, 5, c], B[:, 5, c + 2] = gz, gx
        kk, gg = zp[s:s + chunk, K.ZP_K], zp[s:s + chunk, K.ZP_G]
        lam = kk - 2.0 * gg / 3.0
        D = np.zeros((n, 6, 6))
        D[:, :3, :3] = lam[:, None, None]
        for i in range(3):
            D[:, i, i] += 2.0 * gg
            D[:, 3 + i, 3 + i] = gg
        ke = np.einsum("nki,nkl,nlj->nij", B, D, B) * wvol[s:s + chunk, None, None]
        rows = np.abs(ke).sum(axis=2).reshape(n * 4, 3)
        np.add.at(stiff, t.ravel(), rows)


def cell_stiffness_bound(stiff, cells):
    """Adds, per node and component (stiff (n, 3)), the absolute row sum of
    each linear cell's matrix E K."""
    rows = np.abs(cells.K).sum(axis=2).reshape(-1, 8, 3)                  # (nk, 8, 3)
    np.add.at(stiff, cells.nodes.ravel(), (cells.scale[:, None, None] * rows[cells.kind]).reshape(-1, 3))


def _contact_rows(sc):
    """Per sub-contact (n, 3): area times the absolute row sums of its
    stiffness C = k_n n n^T + k_s (t1 t1^T + t2 t2^T)."""
    n = sc.area.shape[0]
    ax = sc.axes.reshape(n, 3, 3)
    kn, ks = sc.par[:, K.JP_KN], sc.par[:, K.JP_KS]
    C = (kn[:, None, None] * np.einsum("ni,nj->nij", ax[:, 0], ax[:, 0])
         + ks[:, None, None] * (np.einsum("ni,nj->nij", ax[:, 1], ax[:, 1])
                                + np.einsum("ni,nj->nij", ax[:, 2], ax[:, 2])))
    return np.abs(C).sum(axis=2) * sc.area[:, None]


def _contact_rowmax(sc):
    """Per sub-contact: area times the largest absolute row sum of its
    stiffness (any orientation of its axes: rigid blocks)."""
    return _contact_rows(sc).max(axis=1)


def rigid_contact_stiffness(kt, kr, sc):
    """Gershgorin bounds of the contact stiffness of rigid bodies, for any
    orientation: a sub-contact of stiffness matrix C (as in
    ``contact_stiffness``, absolute row sums at most c) between bodies with
    levers r_A, r_B couples their velocities through G = [I, -[r]x]; the
    rows of the 12 x 12 block G^T C G sum, in absolute value, to at most
    c (2 + sqrt2 (|r_A| + |r_B|)) for a translation and
    c |r| (2 sqrt2 + 2 |r_A| + 2 |r_B|) for a rotation of the body with
    lever r (|[r]x| has row sums at most sqrt2 |r|)."""
    if sc.area.shape[0] == 0:
        return
    c = _contact_rowmax(sc)
    r = np.linalg.norm(sc.lever, axis=2)                  # (n, 2)
    rsum = r.sum(axis=1)
    s2 = math.sqrt(2.0)
    for side in range(2):
        np.add.at(kt, sc.body[:, side], c * (2.0 + s2 * rsum))
        np.add.at(kr, sc.body[:, side], c * r[:, side] * (2.0 * s2 + 2.0 * rsum))


def contact_stiffness(stiff, sc):
    """Gershgorin bound of the sub-contacts' stiffness, per node and component
    (stiff (n, 3)): a sub-contact couples its (up to 8) interpolated nodes
    through C = area (k_n n n^T + k_s (t1 t1^T + t2 t2^T)); the absolute row
    sum of component d of node i is |w_i| (sum_j |w_j|) sum_e |C_de|."""
    if sc.area.shape[0] == 0:
        return
    rows = _contact_rows(sc)
    w = np.abs(sc.w)
    wsum = w.sum(axis=1)
    np.add.at(stiff, sc.nodes.ravel(), (w[:, :, None] * (wsum[:, None] * rows)[:, None, :]).reshape(-1, 3))


def scaled_masses(k, alpha, safety, dt=1.0):
    """Quasi-static density scaling: m_i = (1 + alpha) k_i (dt / (2 s))^2 per
    degree of freedom, so that dt is s times the critical step (1 where
    k_i = 0)."""
    return np.where(k > 0, (1.0 + alpha) * k * (dt / (2.0 * safety)) ** 2, 1.0)


def critical_step(mass, k, alpha, free):
    """dt_crit = 2 min over free degrees of freedom sqrt(m / ((1 + alpha) k));
    ``free`` selects the rows (nodes or bodies)."""
    with np.errstate(divide="ignore"):
        return float(np.min(2.0 * np.sqrt(mass[free] / ((1.0 + alpha) * k[free])), initial=np.inf))


def physical_masses(phys, free, field):
    """Dynamic mode: the physical masses (or inertias); a free degree of
    freedom needs a positive one; prescribed ones get 1 where they have none."""
    rows = free[:, None] if phys.ndim == 2 else free
    if np.any(rows & (phys <= 0)):
        raise InputError(field, "dynamic mode needs a positive density for every block")
    mass = phys.copy()
    mass[~free] = np.where(mass[~free] > 0, mass[~free], 1.0)
    return mass


def time_step(mode, crit, safety, dt):
    """(dt, dt_crit): quasi-static, a unit pseudo step at ``safety`` of the
    critical step; dynamic, ``dt`` (default: ``safety`` times the smallest
    critical step of ``crit``), refused above the critical step."""
    if mode == QUASI_STATIC:
        return 1.0, 1.0 / safety
    dt_crit = min(crit)
    if dt is None:
        dt = safety * dt_crit
    if not (dt > 0) or dt > dt_crit:
        raise InputError("solver.dt", f"time step {dt!r} s is above the critical step "
                         f"{dt_crit:.6g} s (2 min sqrt(m / ((1 + damping) k))) or not positive")
    return float(dt), dt_crit
