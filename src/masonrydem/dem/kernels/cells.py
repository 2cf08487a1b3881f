"""Elastic cells computed as linear (elements.py): f = -E K u per cell."""
import numpy as np
from numba import njit

_INLINE = dict(cache=True, inline="always", error_model="numpy")


@njit(**_INLINE)
def cell_forces(nodes, cells, scratch):
    """Adds every cell's nodal forces -scale K u to nodes.f, in every lane:
    the corners' current displacements gathered into the columns of
    scratch.U (column c S + b: cell c of lane b), one matrix product K U
    per cell kind, K^T U (BLAS), the columns of the result scattered back:
    column c S + b of K^T U is the row of U K that a run alone computes,
    the same products summed in the same order (K is symmetric only to
    round-off, so the transpose, not K)."""
    u, f = nodes.u, nodes.f
    nl = u.shape[2]
    ix, kind, scale, K = cells.nodes, cells.kind, cells.scale, cells.K
    U, F = scratch.U, scratch.F
    nc = ix.shape[0]
    for c in range(nc):
        for a in range(8):
            nd = ix[c, a]
            for d in range(3):
                for b in range(nl):
                    U[3 * a + d, c * nl + b] = u[nd, d, b]
    for k in range(K.shape[0]):
        np.dot(K[k].T, U, F[k])
    for c in range(nc):
        k = kind[c]
        for a in range(8):
            nd = ix[c, a]
            for d in range(3):
                for b in range(nl):
                    f[nd, d, b] -= scale[c, b] * F[k, 3 * a + d, c * nl + b]
