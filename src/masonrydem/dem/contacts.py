"""Contacts found from the initial geometry: joints between touching box
faces, and the bearings of rigid strips (supports, load lines); both as
sub-contacts, points on a face that each carry an area."""
from dataclasses import dataclass, field

import numpy as np

from . import kernels as K
from .blocks import (GEOM_TOL, box, check_3, face_points, face_quadrature, face_refine, local_axes,
                     refine_axes)
from .memo import exact, memoized
from ..errors import InputError
from .laws import JointProps


@dataclass
class Contact:
    """A joint: the touching part of two faces."""
    id: int
    block_a: int          # the side whose face gridpoints carry the sub-contacts
    block_b: int
    axis: int
    normal: np.ndarray    # from A to B
    area: float
    sc: slice             # its sub-contacts
    props: JointProps = None


@dataclass
class Strip:
    """A rigid bearing strip (a support or load line): one node with a
    prescribed velocity, bearing on block faces through compression-only,
    frictionless sub-contacts of stiffness kn (Pa/m).  A strip that turns
    (a roller or a line load: its resultant stays on its centre line) turns
    about the long side of its rectangle: deformable blocks give it a
    second node, whose component ``axis`` is the turn times the half width
    (a sub-contact at xi half widths from the centre line moves with the
    strip's node plus xi times it); a rigid strip body turns about that
    axis.  Components in ``free`` are not prescribed: ``force`` acts on
    them (a platen held by a force)."""
    name: str
    axis: int
    normal: int
    kn: float
    sc: slice
    area: float
    x0: np.ndarray        # its node's position: the centre of its rectangle
    velocity: np.ndarray
    index: int            # its number among the strips: its node is Assembly.strip_nodes[index]
    turn: int = -1        # the global axis it turns about (-1: it does not turn)
    turn_index: int = -1  # its number among the strips that turn: its second node is Assembly.turn_nodes[turn_index]
    free: tuple = ()
    force: np.ndarray = None


@dataclass
class SubContacts:
    """Growing blocks of sub-contacts (packed into a kernels.Contacts): a
    joint's or a strip's sub-contacts are added at once, as arrays."""
    chunks: list = field(default_factory=list)
    n: int = 0

    def add_many(self, nodes_a, w_a, cnt_a, nodes_b, w_b, cnt_b, axes, area, par, points):
        """Sub-contacts i = 0 .. m-1: side A's nodes and weights the first
        cnt_a[i] of row i of nodes_a, w_a (at most 4, the others node 0 and
        weight 0), side B's likewise; ``axes`` and ``par`` shared, ``area``
        and ``points`` (m, 3) each its own."""
        m = len(area)
        nodes = np.zeros((m, 8), np.int64)
        w = np.zeros((m, 8))
        ka, kb = np.shape(nodes_a)[1], np.shape(nodes_b)[1]
        nodes[:, :ka], w[:, :ka] = nodes_a, w_a
        nodes[:, 4:4 + kb], w[:, 4:4 + kb] = nodes_b, w_b
        cnt = np.stack([np.broadcast_to(cnt_a, m), np.broadcast_to(cnt_b, m)], axis=1)
        self.chunks.append((nodes, w, cnt, np.broadcast_to(axes, (m, 9)), np.asarray(area, float),
                            np.broadcast_to(par, (m, K.N_JP)), np.asarray(points, float).reshape(m, 3)))
        self.n += m

    def __len__(self):
        return self.n

    def pack(self):
        """(kernels.Contacts without rigid levers, positions (n, 3)).  The
        axes, parameters, state and work space are Fortran-ordered, a column
        per quantity, so that the law's loop over the sub-contacts compiles to
        vector code (kernels/joints.py)."""
        n = self.n
        empty = (np.zeros((0, 8), np.int64), np.zeros((0, 8)), np.zeros((0, 2), np.int64), np.zeros((0, 9)),
                 np.zeros(0), np.zeros((0, K.N_JP)), np.zeros((0, 3)))
        nodes, w, cnt, axes, area, par, points = (np.concatenate(parts) for parts in zip(empty, *self.chunks))
        return K.Contacts(
            nodes=nodes.astype(np.int32), cnt=cnt.astype(np.int64), w=w,     # int32: half the bytes a step streams
            body=np.zeros((0, 2), np.int64), lever=np.zeros((0, 2, 3)),
            axes=np.asfortranarray(axes), area=area,
            par=np.asfortranarray(par), state=np.zeros((n, K.N_JS), order="F"),
            force=np.zeros((n, 3), order="F"), gptr=np.zeros(1, np.int64), gs=np.zeros(0, np.int64), gw=np.zeros(0),
        ), points


def with_gather(sc, n_nodes):
    """``sc`` with its per-node gather of forces (kernels.Contacts): for
    each node, the sub-contacts that it interpolates, in sub-contact order,
    with their weights (side A +w, side B -w).  Each node then adds its
    sub-contacts' forces in the order a loop over the sub-contacts would
    (the same sums, bit for bit), without scattered writes."""
    n = sc.area.shape[0]
    k = np.arange(8)
    used = np.where(k < 4, k[None, :] < sc.cnt[:, :1], k[None, :] - 4 < sc.cnt[:, 1:])     # (n, 8)
    s_idx = np.broadcast_to(np.arange(n)[:, None], (n, 8))[used]
    node = sc.nodes[used]
    w = np.where(k < 4, sc.w, -sc.w)[used]
    order = np.lexsort((s_idx, node))
    gptr = np.zeros(n_nodes + 1, np.int64)
    np.add.at(gptr, node + 1, 1)
    return sc._replace(gptr=np.cumsum(gptr), gs=s_idx[order].astype(np.int32), gw=w[order])


def find_joints(blocks, law, props, refine, rule="simpson"):
    """The joints between touching box faces: (contacts, sub-contacts).
    The sub-contacts are the points of a rule exact for the bilinear
    fields of both faces (blocks.face_quadrature on the union of their
    grids), each interpolated on both faces.  ``props``: a JointProps, or a
    function (block_a, block_b) -> JointProps; ``refine``: per global axis
    (x, y, z), each interval of the rule split that many times along it (or
    a function (block_a, block_b) -> that refinement).  ``rule``
    'vertices': 3DEC's scheme, sub-contacts at the vertices of both faces'
    grids with their tributary areas (blocks.trapezoid)."""
    boxes = [b for b in blocks if b.is_box]
    contacts, sc = [], SubContacts()
    for i, j, axis, rect in _touching(tuple(b.geometry for b in boxes)):
        contacts.append(_joint(len(contacts), sc, boxes[i], boxes[j], axis, rect, law, props, refine, rule))
    return contacts, sc


@memoized(exact)
def _touching(geometries):
    """(i, j, axis, rect) of each pair of touching box faces, box i's face
    at its hi side on box j's lo side, overlapping in the rectangle rect
    (a tuple; read-only: memo.py)."""
    boxes, out = [box(g) for g in geometries], []
    for i, b1 in enumerate(boxes):
        for k, b2 in enumerate(boxes[i + 1:], i + 1):
            for axis in range(3):
                for lo, hi, (lower, upper) in ((i, k, (b1, b2)), (k, i, (b2, b1))):
                    if abs(lower.hi[axis] - upper.lo[axis]) > GEOM_TOL:
                        continue
                    p, q = lower.face_axes(axis)
                    rect = ((max(lower.lo[p], upper.lo[p]), min(lower.hi[p], upper.hi[p])),
                            (max(lower.lo[q], upper.lo[q]), min(lower.hi[q], upper.hi[q])))
                    if min(rect[0][1] - rect[0][0], rect[1][1] - rect[1][0]) <= GEOM_TOL:
                        continue
                    out.append((lo, hi, axis, rect))
    return tuple(out)


@memoized(exact)
def _upper_finer(lower, upper, axis, rect):
    """Whether the upper face has more gridpoints in the overlap."""
    return box(upper).nodes_in_rect(axis, rect) > box(lower).nodes_in_rect(axis, rect)


@memoized(exact)
def _joint_points(ga, gb, side_a, side_b, axis, rect, refine, rule, coord):
    """A joint's sub-contacts on the face of the box ga (side A) against
    the face of gb: (nodes, weights, counts of A, of B, areas, points)
    (read-only: memo.py)."""
    a, b = box(ga), box(gb)
    P, Q, A = face_quadrature(rect, zip(a.face_grid(axis), b.face_grid(axis)), face_refine(refine, axis), rule)
    na, wa, ca = a.interpolate_points(axis, side_a, P, Q)
    nb, wb, cb = b.interpolate_points(axis, side_b, P, Q)
    return na, wa, ca, nb, wb, cb, A, face_points(axis, coord, P, Q)


def _joint(cid, sc, lower, upper, axis, rect, law, props, refine, rule):
    # sub-contacts on the finer face (more gridpoints in the overlap)
    if _upper_finer(lower.geometry, upper.geometry, axis, rect):
        a, b, side_a, side_b, sign = upper, lower, 0, 1, -1.0
    else:
        a, b, side_a, side_b, sign = lower, upper, 1, 0, 1.0
    props = props(a, b) if callable(props) else props
    refine = refine_axes(refine(a, b) if callable(refine) else refine, f"joints[{cid}].refine")
    if not isinstance(props, JointProps):
        raise InputError("joints.props", f"expected JointProps, got {type(props).__name__}")
    props.validate(f"joints[{cid}] (blocks {a.id}-{b.id})", law)
    row = props.row()
    axes = local_axes(axis, sign)
    start = len(sc)
    na, wa, ca, nb, wb, cb, A, points = _joint_points(a.geometry, b.geometry, side_a, side_b, axis, rect, refine,
                                                      rule, lower.hi[axis])
    sc.add_many(na, wa, ca, nb, wb, cb, axes, A, row, points)
    return Contact(cid, a.id, b.id, axis, axes[:3].copy(), float(A.sum()), slice(start, len(sc)), props)


def faces_on_plane(blocks, axis, coord, normal, rect):
    """(block, side, clipped rectangle) of the box faces lying on the plane
    x[axis] = coord whose outward normal is ``normal`` (+1 or -1) times
    e_axis and that overlap ``rect`` = ((plo, phi), (qlo, qhi)) in the
    plane's coordinates (p, q) = (axis+1, axis+2) mod 3."""
    if normal not in (1, -1):
        raise InputError("normal", f"must be +1 or -1, got {normal!r}")
    out = []
    side = 1 if normal > 0 else 0
    for b in blocks:
        if not b.is_box or abs((b.hi[axis] if side else b.lo[axis]) - coord) > GEOM_TOL:
            continue
        p, q = b.face_axes(axis)
        r = ((max(b.lo[p], rect[0][0]), min(b.hi[p], rect[0][1])),
             (max(b.lo[q], rect[1][0]), min(b.hi[q], rect[1][1])))
        if min(r[0][1] - r[0][0], r[1][1] - r[1][0]) > GEOM_TOL:
            out.append((b, side, r))
    return out


def bearing_strip(sc, blocks, index, name, axis, coord, normal, rect, kn, velocity, refine, turn_index=-1,
                  friction=0.0):
    """Strip number ``index`` (``Model.add_strip``): its bearing sub-contacts,
    added to ``sc``, at the points of the composite Simpson rule on the
    faces of ``blocks`` that it covers (refined ``refine`` per global axis),
    side B the strip (-(index + 1) until the assembly numbers its node).
    A strip that turns (``turn_index`` >= 0) turns about the long side of
    its rectangle; on deformable blocks side B also holds its second node
    (-(turn_index + 1)) with the weight xi, the point's distance from the
    centre line in half widths.  ``friction``: its Coulomb friction
    coefficient on the faces (tangential stiffness kn where it is above 0)."""
    where = f"strips.{name}"
    if kn is None or not np.isfinite(kn) or kn <= 0:
        raise InputError(f"{where}.kn", f"must be a positive stiffness, got {kn!r}")
    velocity = check_3(f"{where}.velocity", velocity)
    p, q = (axis + 1) % 3, (axis + 2) % 3
    # the long side (p, or q if longer) is the turning axis; xi runs across it
    long_p = rect[0][1] - rect[0][0] >= rect[1][1] - rect[1][0]
    across = rect[1] if long_p else rect[0]
    centre, half = 0.5 * (across[0] + across[1]), 0.5 * (across[1] - across[0])
    deformable = not any(b.rigid for b in blocks)
    if not (np.isfinite(friction) and friction >= 0):
        raise InputError(f"{where}.friction", f"must be a non-negative number, got {friction!r}")
    row = np.zeros(K.N_JP)
    row[K.JP_KN] = kn
    if friction > 0:
        row[K.JP_KS], row[K.JP_TANPHI] = kn, friction
    axes = local_axes(axis, float(normal))
    start, area = len(sc), []
    for b, side, r in faces_on_plane(blocks, axis, coord, normal, rect):
        P, Q, A = face_quadrature(r, zip(b.face_grid(axis)), face_refine(refine, axis))
        na, wa, ca = b.interpolate_points(axis, side, P, Q)
        pts = face_points(axis, coord, P, Q)
        if turn_index >= 0 and deformable:
            nb = np.broadcast_to([-(index + 1), -(turn_index + 1)], (len(A), 2))
            wb = np.stack([np.ones(len(A)), (pts[:, q if long_p else p] - centre) / half], axis=1)
            sc.add_many(na, wa, ca, nb, wb, 2, axes, A, row, pts)
        else:
            sc.add_many(na, wa, ca, np.full((len(A), 1), -(index + 1)), np.ones((len(A), 1)), 1, axes, A, row, pts)
        area += A.tolist()
    if not area:
        raise InputError(f"{where}.rect", "the strip touches no block face")
    x0 = np.zeros(3)
    x0[axis], x0[p], x0[q] = coord, np.mean(rect[0]), np.mean(rect[1])
    return Strip(name, axis, int(normal), float(kn), slice(start, len(sc)), float(sum(area)), x0,
                 velocity, index, turn=(p if long_p else q) if turn_index >= 0 else -1, turn_index=turn_index)
