"""Elastic cells computed as linear: the nodal forces of an elastic
hexahedral cell are a fixed matrix times its nodal displacements,
f = -E K u, one 24 x 24 matrix K per cell shape (sizes and Poisson's
ratio), scaled by the cell's Young's modulus (kernels.cells).

Two cells, both for boxes (``numerics.elastic_element``):

* ``tet10``: the solver's own cell, two overlays of 5 constant-strain
  tetrahedra with mixed discretization (mesh.py), each weighted 1/2: its
  incremental stress update is linear, so summed over the steps it is
  exactly K u.  Same results as the zones, in one matrix-vector product.
* ``hex8i``: the trilinear hexahedron with incompatible modes (Wilson,
  Taylor, Beresford & Wilson 1973; Taylor, Beresford & Wilson 1976): nine
  internal modes (1 - xi^2, 1 - eta^2, 1 - zeta^2 per component) condensed
  out, so that a rectangular cell bends exactly (a linear stress through
  its depth), where constant-strain tetrahedra need many cells through a
  unit's thickness (they lock in bending).

Node order: corner c = i + 2 j + 4 k at offset (i, j, k); degrees of
freedom 3 c + d.
"""
import itertools

import numpy as np

from .mesh import OVERLAY_A, OVERLAY_B, orient, tet_geometry

ELEMENTS = ("tet10", "hex8i")
# corner offsets (i, j, k) and their natural coordinates (+-1)
_OFFSETS = np.array([[c & 1, (c >> 1) & 1, (c >> 2) & 1] for c in range(8)], float)
_XI = 2.0 * _OFFSETS - 1.0


def elasticity(nu, E=1.0):
    """D (Voigt xx, yy, zz, xy, yz, zx, engineering shear strains)."""
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    D = np.zeros((6, 6))
    D[:3, :3] = lam
    D[np.arange(3), np.arange(3)] += 2 * mu
    D[np.arange(3, 6), np.arange(3, 6)] = mu
    return D


def strain_matrix(grads):
    """B (6 x 3n) of shape-function gradients ``grads`` (n, 3)."""
    n = grads.shape[0]
    B = np.zeros((6, 3 * n))
    for a, (gx, gy, gz) in enumerate(grads):
        c = 3 * a
        B[0, c], B[1, c + 1], B[2, c + 2] = gx, gy, gz
        B[3, c], B[3, c + 1] = gy, gx
        B[4, c + 1], B[4, c + 2] = gz, gy
        B[5, c], B[5, c + 2] = gz, gx
    return B


def tet10_stiffness(size, nu):
    """K (E = 1) of the mixed-discretization cell of ``size`` (hx, hy, hz):
    per overlay, the volumetric strain of each tetrahedron replaced by the
    overlay's volume-weighted mean (as kernels.zones does), forces
    f = -sum w V B^T sigma with w = 1/2."""
    x = _OFFSETS * np.asarray(size, float)
    D = elasticity(nu)
    m = np.array([1.0, 1, 1, 0, 0, 0])
    K = np.zeros((24, 24))
    for overlay in (OVERLAY_A, OVERLAY_B):
        tets = orient(x, overlay)
        dn, vol = tet_geometry(x, tets)
        Bs = []
        for t in range(5):
            g = dn[t].reshape(3, 3)
            grads = np.vstack([-g.sum(axis=0), g])            # rows: grad N of the tet's 4 nodes
            Bt = np.zeros((6, 24))
            for a, nd in enumerate(tets[t]):
                Bt[:, 3 * nd:3 * nd + 3] += strain_matrix(grads[a:a + 1])
            Bs.append(Bt)
        mbar = sum(v * (m @ B) for v, B in zip(vol, Bs)) / vol.sum()
        for v, B in zip(vol, Bs):
            Bmix = B + np.outer(m, mbar - m @ B) / 3.0
            K += 0.5 * v * B.T @ D @ Bmix
    return K


def hex8i_stiffness(size, nu):
    """K (E = 1) of the box cell of ``size`` with incompatible modes,
    2 x 2 x 2 Gauss points, the internal modes condensed:
    K = K_cc - K_ci K_ii^-1 K_ic."""
    h = np.asarray(size, float)
    J = h / 2.0                                   # dx / dxi per axis (a box: constant)
    D = elasticity(nu)
    g = 1.0 / np.sqrt(3.0)
    K = np.zeros((33, 33))
    for xi in itertools.product((-g, g), repeat=3):
        xi = np.array(xi)
        # trilinear: dN_a/dxi_d = xi_a,d / 8 prod_{e != d} (1 + xi_a,e xi_e)
        f = 1.0 + _XI * xi                                     # (8, 3)
        dN = np.stack([_XI[:, d] / 8.0 * np.prod(np.delete(f, d, axis=1), axis=1) for d in range(3)], axis=1)
        # incompatible modes 1 - xi_d^2: d/dxi_d = -2 xi_d
        dI = np.diag(-2.0 * xi)                                # (3 modes, 3 directions)
        grads = np.vstack([dN, dI]) / J                        # physical gradients (11, 3)
        B = strain_matrix(grads)                               # (6, 33)
        K += B.T @ D @ B * np.prod(J)
    Kcc, Kci, Kii = K[:24, :24], K[:24, 24:], K[24:, 24:]
    return Kcc - Kci @ np.linalg.solve(Kii, Kci.T)


def cell_stiffness(element, size, nu):
    """K (24 x 24, E = 1) of one cell."""
    return {"tet10": tet10_stiffness, "hex8i": hex8i_stiffness}[element](size, nu)
