"""Meshing of blocks into constant-strain tetrahedra.

A box is divided into nx*ny*nz hexahedral cells; each cell is split twice
into 5 tetrahedra (the two "overlays" of the classic mixed discretization,
Marti & Cundall 1982), 10 tetrahedra per cell, each weighted 1/2.  Each
overlay is one mixed-discretization group: its volumetric strain rate is the
volume-weighted mean over its 5 tetrahedra.
"""
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .memo import exact, memoized

# Hexahedron corner c = i + 2 j + 4 k for the corner at offset (i, j, k).
# Overlay A: corner tetrahedra at corners 1, 2, 4, 7 and the central one on
# 0, 3, 5, 6; overlay B: corners 0, 3, 5, 6 and the central one on 1, 2, 4, 7.
OVERLAY_A = np.array([[1, 0, 3, 5], [2, 0, 3, 6], [4, 0, 5, 6], [7, 3, 5, 6],
                      [0, 3, 5, 6]])
OVERLAY_B = np.array([[0, 1, 2, 4], [3, 1, 2, 7], [5, 1, 4, 7], [6, 2, 4, 7],
                      [1, 2, 4, 7]])


@dataclass
class TetMesh:
    """Nodes, tetrahedra and mixed-discretization groups of one block.

    groups: tetrahedra of group g are tets[gptr[g]:gptr[g+1]];
    gnodes[gnptr[g]:gnptr[g+1]] are the nodes of the group's cell (used for
    the crack-band width); weight: the tetrahedra's weights (1/2 for
    overlays, 1 otherwise); cells: a box's hexahedral cells, their corner
    c = i + 2 j + 4 k at offset (i, j, k) (none for unstructured blocks)."""
    nodes: np.ndarray
    tets: np.ndarray
    weight: np.ndarray
    gptr: np.ndarray
    gnodes: np.ndarray
    gnptr: np.ndarray
    cells: np.ndarray = None


def box_mesh(lo, hi, cells):
    """Structured mesh of the box [lo, hi] with cells = (nx, ny, nz)
    (read-only: memo.py)."""
    return _box_mesh(np.asarray(lo, float), np.asarray(hi, float), tuple(int(c) for c in cells))


@memoized(exact)
def _box_mesh(lo, hi, cells):
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    nx, ny, nz = (int(c) for c in cells)
    xs = [np.linspace(lo[d], hi[d], n + 1) for d, n in enumerate((nx, ny, nz))]
    X, Y, Z = np.meshgrid(*xs, indexing="ij")
    # node index i + (nx+1) (j + (ny+1) k): flatten in Fortran order
    nodes = np.column_stack([X.ravel(order="F"), Y.ravel(order="F"),
                             Z.ravel(order="F")])

    def nid(i, j, k):
        return i + (nx + 1) * (j + (ny + 1) * k)

    i, j, k = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz),
                          indexing="ij")
    i, j, k = i.ravel(order="F"), j.ravel(order="F"), k.ravel(order="F")
    corners = np.stack([nid(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))
                        for c in range(8)], axis=1)          # (ncell, 8)
    ncell = corners.shape[0]
    # per cell: overlay A (5 tets) then overlay B (5 tets)
    local = np.concatenate([OVERLAY_A, OVERLAY_B])             # (10, 4)
    tets = corners[:, local].reshape(ncell * 10, 4)
    tets = orient(nodes, tets)
    weight = np.full(ncell * 10, 0.5)
    gptr = np.arange(0, ncell * 10 + 1, 5)
    gnodes = np.repeat(corners, 2, axis=0).ravel()             # 8 per group
    gnptr = np.arange(0, 2 * ncell * 8 + 1, 8)
    return TetMesh(nodes, tets, weight, gptr, gnodes, gnptr, corners)


def tet_mesh(nodes, tets):
    """An unstructured tetrahedral block: every tetrahedron is its own group
    (no mixed discretization)."""
    nodes = np.asarray(nodes, float)
    tets = orient(nodes, np.asarray(tets, np.int64))
    nt = tets.shape[0]
    return TetMesh(nodes, tets, np.ones(nt), np.arange(nt + 1),
                   tets.ravel().copy(), np.arange(0, 4 * nt + 1, 4))


def orient(nodes, tets):
    """Reorders each tetrahedron so that its signed volume is positive."""
    tets = np.array(tets, np.int64, copy=True)
    e = nodes[tets[:, 1:]] - nodes[tets[:, :1]]
    neg = det3(e) < 0.0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2], tets[neg, 1].copy()
    return tets


def tet_geometry(nodes, tets):
    """Volumes and shape-function gradients of constant-strain tetrahedra.

    With E = [x1-x0; x2-x0; x3-x0] (rows), grad N_a (a = 1..3) are the
    columns of E^-1 and V = det(E)/6.  Returns (dn, vol) with
    dn[t] = (grad N_1, grad N_2, grad N_3) flattened (9 values).
    Refuses degenerate tetrahedra (V <= 1e-12 of the mean cell volume)."""
    e = nodes[tets[:, 1:]] - nodes[tets[:, :1]]
    det = det3(e)
    vol = det / 6.0
    scale = np.abs(vol).mean() if vol.size else 1.0
    bad = np.flatnonzero(vol <= 1e-12 * scale)
    if bad.size:
        raise InputError("mesh.tets", f"{bad.size} degenerate tetrahedra (zero or "
                         f"negative volume), first: {bad[0]} with nodes "
                         f"{tets[bad[0]].tolist()}")
    # the columns of E^-1 are the rows of cof(E) / det(E)
    dn = cofactors(e).reshape(-1, 9) / det[:, None]
    return np.ascontiguousarray(dn), vol


def cofactors(e):
    """The cofactor matrices of the 3x3 matrices e (..., 3, 3), in closed
    form: the same bits on every CPU (LAPACK's det and inv pick their
    kernels by CPU: docs/known-problems.md)."""
    c = np.empty_like(e)
    for i in range(3):
        i1, i2 = (i + 1) % 3, (i + 2) % 3
        for j in range(3):
            j1, j2 = (j + 1) % 3, (j + 2) % 3
            c[..., i, j] = e[..., i1, j1] * e[..., i2, j2] - e[..., i1, j2] * e[..., i2, j1]
    return c


def det3(e):
    """The determinants of the 3x3 matrices e (..., 3, 3), in closed form."""
    c = cofactors(e)
    return e[..., 0, 0] * c[..., 0, 0] + e[..., 0, 1] * c[..., 0, 1] + e[..., 0, 2] * c[..., 0, 2]
