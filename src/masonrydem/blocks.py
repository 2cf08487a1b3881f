"""Blocks: boxes meshed into tetrahedra (deformable) or rigid boxes, and
the geometry of their faces (grids, interpolation, sub-contact points)."""
from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .laws import Elastic

GEOM_TOL = 1e-9  # m: faces closer than this touch


@dataclass
class Block:
    id: int
    material: Elastic
    mesh: object
    node0: int                    # first global node index
    lo: np.ndarray = None         # boxes only
    hi: np.ndarray = None
    cells: tuple = None           # of a rigid box: the grid of its faces' sub-contacts
    rigid: bool = False

    @property
    def n_nodes(self):
        return 1 if self.rigid else self.mesh.nodes.shape[0]

    @property
    def centroid(self):
        return 0.5 * (self.lo + self.hi)

    @property
    def is_box(self):
        return self.cells is not None

    def face_axes(self, axis):
        return (axis + 1) % 3, (axis + 2) % 3

    def face_grid(self, axis):
        p, q = self.face_axes(axis)
        gp = np.linspace(self.lo[p], self.hi[p], self.cells[p] + 1)
        gq = np.linspace(self.lo[q], self.hi[q], self.cells[q] + 1)
        return gp, gq

    def face_node(self, axis, side, ip, iq):
        """Global index of the node at (ip, iq) of the face normal to
        ``axis`` on side 0 (lo) or 1 (hi)."""
        p, q = self.face_axes(axis)
        idx = [0, 0, 0]
        idx[axis] = 0 if side == 0 else self.cells[axis]
        idx[p], idx[q] = ip, iq
        nx, ny = self.cells[0], self.cells[1]
        return self.node0 + idx[0] + (nx + 1) * (idx[1] + (ny + 1) * idx[2])

    def interpolate(self, axis, side, P, Q):
        """Bilinear interpolation on the face grid at (P, Q): (nodes, weights)
        with zero weights dropped; a rigid block's point moves with its one
        node (and its rotation: the lever is the point's offset)."""
        if self.rigid:
            return [self.node0], [1.0]
        gp, gq = self.face_grid(axis)
        ip = int(np.clip(np.searchsorted(gp, P) - 1, 0, gp.size - 2))
        iq = int(np.clip(np.searchsorted(gq, Q) - 1, 0, gq.size - 2))
        xi = float(np.clip((P - gp[ip]) / (gp[ip + 1] - gp[ip]), 0.0, 1.0))
        eta = float(np.clip((Q - gq[iq]) / (gq[iq + 1] - gq[iq]), 0.0, 1.0))
        cand = [((ip, iq), (1 - xi) * (1 - eta)), ((ip + 1, iq), xi * (1 - eta)),
                ((ip, iq + 1), (1 - xi) * eta), ((ip + 1, iq + 1), xi * eta)]
        nodes, weights = [], []
        for (a, b), wgt in cand:
            if wgt > 1e-12:
                nodes.append(self.face_node(axis, side, a, b))
                weights.append(wgt)
        s = sum(weights)
        return nodes, [wgt / s for wgt in weights]

    def nodes_in_rect(self, axis, rect):
        gp, gq = self.face_grid(axis)
        (plo, phi), (qlo, qhi) = rect
        return (int(np.sum((gp >= plo - GEOM_TOL) & (gp <= phi + GEOM_TOL)))
                * int(np.sum((gq >= qlo - GEOM_TOL) & (gq <= qhi + GEOM_TOL))))

    def face_points(self, axis, rect, refine=1):
        """Sub-contact points of this block's face (normal to ``axis``) over
        the rectangle ``rect`` = ((plo, phi), (qlo, qhi)) in the face's
        coordinates.  The points are the face gridpoints (of a grid refined
        ``refine`` times); each carries the area of its dual cell (halfway
        to its neighbours) clipped to ``rect``; it sits at the gridpoint
        when that lies in ``rect`` (the conforming case: consistent nodal
        lumping), else at the centroid of the clipped cell (non-conforming
        faces).  The dual cells tile the face, so the areas sum exactly to
        the area of rect (inside the face).  Returns (P, Q, area)
        arrays."""
        gp, gq = self.face_grid(axis)
        out = []
        for g, (rlo, rhi) in zip((gp, gq), rect):
            pts = np.linspace(g[0], g[-1], refine * (g.size - 1) + 1)
            edges = np.concatenate([[g[0]], 0.5 * (pts[1:] + pts[:-1]), [g[-1]]])
            lo = np.maximum(edges[:-1], rlo)
            hi = np.minimum(edges[1:], rhi)
            length = np.maximum(hi - lo, 0.0)
            inside = (pts >= rlo - GEOM_TOL) & (pts <= rhi + GEOM_TOL)
            out.append((np.where(inside, pts, 0.5 * (lo + hi)), length))
        (cp, lp), (cq, lq) = out
        P, Q = np.meshgrid(cp, cq, indexing="ij")
        A = np.outer(lp, lq)
        keep = A > 1e-14 * A.sum()
        return P[keep], Q[keep], A[keep]



def face_point(axis, coord, P, Q):
    """The point (x, y, z) at (P, Q) of the plane x[axis] = coord, in the
    plane's coordinates (p, q) = (axis+1, axis+2) mod 3."""
    pt = np.zeros(3)
    pt[axis], pt[(axis + 1) % 3], pt[(axis + 2) % 3] = coord, P, Q
    return pt


def local_axes(axis, sign):
    """(n, t1, t2) of a face normal to ``axis``, n = sign e_axis, as 9 numbers."""
    n = np.zeros(3)
    n[axis] = sign
    t1 = np.zeros(3)
    t1[(axis + 1) % 3] = 1.0
    t2 = np.cross(n, t1)
    return np.concatenate([n, t1, t2])


def check_3(field_, value):
    v = np.asarray(value, float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise InputError(field_, f"must be 3 finite numbers, got {value!r}")
    return v
