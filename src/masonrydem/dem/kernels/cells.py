"""Elastic cells computed as linear (elements.py): f = -E K u per cell."""
import numpy as np
from numba import njit

_INLINE = dict(cache=True, inline="always", error_model="numpy")


@njit(**_INLINE)
def cell_forces(nodes, cells, scratch):
    """Adds every cell's nodal forces -scale K u to nodes.f: the corners'
    current displacements gathered into the rows of scratch.U, one matrix
    product U K per cell kind (BLAS: 2-4 times faster than a product per
    cell), the rows of the result scattered back."""
    u, f = nodes.u, nodes.f
    ix, kind, scale, K = cells.nodes, cells.kind, cells.scale, cells.K
    U, F = scratch.U, scratch.F
    nc = ix.shape[0]
    for c in range(nc):
        for a in range(8):
            nd = ix[c, a]
            U[c, 3 * a] = u[nd, 0]
            U[c, 3 * a + 1] = u[nd, 1]
            U[c, 3 * a + 2] = u[nd, 2]
    for k in range(K.shape[0]):
        np.dot(U, K[k], F[k])           # K symmetric: row c of U K is K u_c
    for c in range(nc):
        e = scale[c]
        k = kind[c]
        for a in range(8):
            nd = ix[c, a]
            f[nd, 0] -= e * F[k, c, 3 * a]
            f[nd, 1] -= e * F[k, c, 3 * a + 1]
            f[nd, 2] -= e * F[k, c, 3 * a + 2]
