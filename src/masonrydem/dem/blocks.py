"""Blocks: boxes meshed into tetrahedra (deformable) or rigid boxes, and
the geometry of their faces (grids, interpolation, sub-contact points)."""
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .laws import Elastic
from .memo import exact, memoized

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
    element: str = "zones"        # zones (tetrahedra) or a linear cell (elements.ELEMENTS)

    @property
    def n_nodes(self):
        return 1 if self.rigid else self.mesh.nodes.shape[0]

    @property
    def centroid(self):
        return 0.5 * (self.lo + self.hi)

    @property
    def is_box(self):
        return self.cells is not None

    @property
    def geometry(self):
        """What a box's faces are: its box, grid, first node and rigidity
        (``box`` makes it a box again)."""
        return self.lo, self.hi, self.cells, self.node0, self.rigid

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
        nodes, weights, count = self.interpolate_points(axis, side, np.array([P]), np.array([Q]))
        return nodes[0, :count[0]].tolist(), weights[0, :count[0]].tolist()

    def interpolate_points(self, axis, side, P, Q):
        """``interpolate`` at the points (P[i], Q[i]): (nodes (n, 4), weights
        (n, 4), count (n,)), each row's nodes and weights first, unused
        slots node 0 and weight 0 (read-only: memo.py)."""
        return _interpolate_points(self.geometry, axis, side, np.asarray(P), np.asarray(Q))

    def _interpolate_points(self, axis, side, P, Q):
        n = P.size
        nodes = np.zeros((n, 4), np.int64)
        weights = np.zeros((n, 4))
        if self.rigid:
            nodes[:, 0] = self.node0
            weights[:, 0] = 1.0
            return nodes, weights, np.ones(n, np.int64)
        gp, gq = self.face_grid(axis)
        ip = np.clip(np.searchsorted(gp, P) - 1, 0, gp.size - 2)
        iq = np.clip(np.searchsorted(gq, Q) - 1, 0, gq.size - 2)
        xi = np.clip((P - gp[ip]) / (gp[ip + 1] - gp[ip]), 0.0, 1.0)
        eta = np.clip((Q - gq[iq]) / (gq[iq + 1] - gq[iq]), 0.0, 1.0)
        cand = [(ip, iq, (1 - xi) * (1 - eta)), (ip + 1, iq, xi * (1 - eta)),
                (ip, iq + 1, (1 - xi) * eta), (ip + 1, iq + 1, xi * eta)]
        count = np.zeros(n, np.int64)
        total = np.zeros(n)
        rows = np.arange(n)
        for a, b, wgt in cand:          # in this order, the weights above 1e-12
            keep = wgt > 1e-12
            nodes[rows[keep], count[keep]] = self.face_node(axis, side, a[keep], b[keep])
            weights[rows[keep], count[keep]] = wgt[keep]
            total = total + np.where(keep, wgt, 0.0)
            count += keep
        weights /= total[:, None]
        return nodes, weights, count

    def nodes_in_rect(self, axis, rect):
        gp, gq = self.face_grid(axis)
        (plo, phi), (qlo, qhi) = rect
        return (int(np.sum((gp >= plo - GEOM_TOL) & (gp <= phi + GEOM_TOL)))
                * int(np.sum((gq >= qlo - GEOM_TOL) & (gq <= qhi + GEOM_TOL))))


def box(geometry):
    """The box of ``geometry`` (Block.geometry): its faces, without a
    material or mesh."""
    lo, hi, cells, node0, rigid = geometry
    return Block(-1, None, None, node0, np.asarray(lo), np.asarray(hi), cells, rigid)


@memoized(exact)
def _interpolate_points(geometry, axis, side, P, Q):
    """Block.interpolate_points of a box's geometry alone."""
    return box(geometry)._interpolate_points(axis, side, P, Q)


def breakpoints(lo, hi, *lines):
    """[lo, hi] cut at every line of ``lines`` inside it, lines closer than
    GEOM_TOL merged: the intervals on which the fields of every face that
    the lines come from are polynomial (bilinear elements)."""
    x = np.concatenate([[lo, hi], *[np.asarray(g, float) for g in lines]])
    x = np.sort(x[(x >= lo) & (x <= hi)])
    keep = np.concatenate([[True], np.diff(x) > GEOM_TOL])
    x = x[keep]
    x[-1] = hi
    return x


def simpson(breaks, refine=1):
    """Composite Simpson (3-point Gauss-Lobatto) rule on the intervals of
    ``breaks``, each split into ``refine`` equal parts: (points, weights).
    Exact for cubics on each interval, so for the product of two linear
    fields: a joint's bending and torsional stiffness come out exact for a
    linear traction field; and with points at the interval ends, a joint's
    edge reaches its strength when the linear field's edge value does (the
    cracking moment f_t b h^2 / 6).  Nodal (trapezoid) weights would
    overestimate both by (1 + 2 / n^2) with n intervals; two-point Gauss
    would get the stiffness but, without end points, a cracking moment up
    to sqrt(3) times too high on one interval."""
    edges = np.concatenate([np.linspace(a, b, refine + 1)[:-1] for a, b in zip(breaks[:-1], breaks[1:])]
                           + [breaks[-1:]])
    h = np.diff(edges)
    pts = np.empty(2 * h.size + 1)
    w = np.zeros(2 * h.size + 1)
    pts[0::2] = edges
    pts[1::2] = 0.5 * (edges[:-1] + edges[1:])
    w[1::2] = 4.0 * h / 6.0
    w[0:-1:2] += h / 6.0
    w[2::2] += h / 6.0
    return pts, w


def trapezoid(breaks, refine=1):
    """Nodal rule on the intervals of ``breaks``, each split into
    ``refine`` equal parts: points at the interval ends, each weighted by
    half its two intervals (3DEC's sub-contacts at the face vertices with
    their tributary areas; its error: ``simpson``)."""
    edges = np.concatenate([np.linspace(a, b, refine + 1)[:-1] for a, b in zip(breaks[:-1], breaks[1:])]
                           + [breaks[-1:]])
    h = np.diff(edges)
    w = np.zeros(edges.size)
    w[:-1] += 0.5 * h
    w[1:] += 0.5 * h
    return edges, w


RULES = {"simpson": simpson, "vertices": trapezoid}


def face_quadrature(rect, lines, refine=(1, 1), rule="simpson"):
    """Points (P, Q) and weights (areas) of the tensor-product composite
    Simpson rule on the rectangle ``rect`` = ((plo, phi), (qlo, qhi)) cut
    by the grid lines of every face involved (a joint: both faces; a strip
    or a pressure: the loaded face): ``lines`` = (p line arrays, q line
    arrays), one array per face; ``refine`` = (r_p, r_q): each interval
    split that many times along p and q.
    The weights sum to the rectangle's area, and their first moments to
    its centroid times its area, whatever the grids: a strip's resultant
    acts on its configured line.  ``rule`` 'vertices': the nodal rule
    (``trapezoid``) instead.  (Read-only: memo.py.)"""
    return _face_quadrature(rect, tuple(tuple(ls) for ls in lines), tuple(refine), rule)


@memoized(exact)
def _face_quadrature(rect, lines, refine, rule):
    (pp, wp), (pq, wq) = (RULES[rule](breakpoints(lo, hi, *ls), r) for (lo, hi), ls, r in zip(rect, lines, refine))
    P, Q = np.meshgrid(pp, pq, indexing="ij")
    return P.ravel(), Q.ravel(), np.outer(wp, wq).ravel()


def refine_axes(refine, where="numerics.subcontact_refine"):
    """A sub-contact refinement as one integer per global axis (x, y, z):
    ``refine`` one integer >= 1 for all axes, or three."""
    r = np.atleast_1d(np.asarray(refine, dtype=object))
    if r.size == 1:
        r = np.repeat(r, 3)
    if r.size != 3 or not all(isinstance(x, (int, np.integer)) and not isinstance(x, bool) and x >= 1 for x in r):
        raise InputError(where, f"must be an integer >= 1 or three of them (x, y, z), got {refine!r}")
    return tuple(int(x) for x in r)


def face_refine(refine, axis):
    """The refinement (r_p, r_q) of a face normal to ``axis`` in its plane's
    coordinates (p, q) = (axis+1, axis+2) mod 3, from one per global axis."""
    return refine[(axis + 1) % 3], refine[(axis + 2) % 3]


def face_point(axis, coord, P, Q):
    """The point (x, y, z) at (P, Q) of the plane x[axis] = coord, in the
    plane's coordinates (p, q) = (axis+1, axis+2) mod 3."""
    pt = np.zeros(3)
    pt[axis], pt[(axis + 1) % 3], pt[(axis + 2) % 3] = coord, P, Q
    return pt


def face_points(axis, coord, P, Q):
    """``face_point`` at the points (P[i], Q[i]): (n, 3)."""
    pts = np.zeros((len(P), 3))
    pts[:, axis], pts[:, (axis + 1) % 3], pts[:, (axis + 2) % 3] = coord, P, Q
    return pts


@memoized(exact)
def local_axes(axis, sign):
    """(n, t1, t2) of a face normal to ``axis``, n = sign e_axis, as 9
    numbers (read-only: memo.py)."""
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
