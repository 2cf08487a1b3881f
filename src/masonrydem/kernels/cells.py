"""Elastic cells computed as linear (elements.py): f = -E K u per cell."""
from numba import njit

_INLINE = dict(cache=True, inline="always", error_model="numpy")


@njit(**_INLINE)
def cell_forces(nodes, cells, scratch):
    """Adds every cell's nodal forces -scale K u (u the corners' current
    displacements, gathered into scratch.ue) to nodes.f."""
    u, f = nodes.u, nodes.f
    ix, kind, scale, K = cells.nodes, cells.kind, cells.scale, cells.K
    ue = scratch.ue
    for c in range(ix.shape[0]):
        for a in range(8):
            nd = ix[c, a]
            ue[3 * a] = u[nd, 0]
            ue[3 * a + 1] = u[nd, 1]
            ue[3 * a + 2] = u[nd, 2]
        k = kind[c]
        e = scale[c]
        for a in range(8):
            nd = ix[c, a]
            for d in range(3):
                r = 3 * a + d
                acc = 0.0
                for b in range(24):
                    acc += K[k, r, b] * ue[b]
                f[nd, d] -= e * acc
