"""Model assembly: blocks, joints found from the initial geometry, bearing
strips, pressures, fixities and monitors, packed into flat arrays.

Blocks are deformable (meshed into tetrahedra; their gridpoints are the
nodes) or rigid (one node each, at the centroid, with three rotations
besides: ``add_box(..., rigid=True)``); a model's blocks are all one or
the other, and its arrays hold only what its blocks need.

Deformable blocks are small-displacement: strains are computed with the
shape functions of the initial geometry and joints keep their initial
local axes, so rigid rotations must stay small (the solver checks this).
Rigid blocks may also rotate by large angles (``Model.large``): the joints'
axes then turn with the block that carries them.
"""
import math
from dataclasses import dataclass, field

import numpy as np

from . import kernels as K
from .errors import InputError
from .laws import Elastic, JointProps, joint_law_id
from .mesh import box_mesh, tet_geometry, tet_mesh

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
    frictionless sub-contacts of stiffness kn (Pa/m)."""
    name: str
    node: int             # global node (set by Model.build)
    axis: int
    normal: int
    kn: float
    sc: slice
    area: float


@dataclass
class _SubContacts:
    """Growing lists of sub-contacts (packed by ``pack``)."""
    nodes: list = field(default_factory=list)
    cnt: list = field(default_factory=list)
    w: list = field(default_factory=list)
    axes: list = field(default_factory=list)
    area: list = field(default_factory=list)
    par: list = field(default_factory=list)
    point: list = field(default_factory=list)   # the sub-contact's position

    def add(self, nodes_a, w_a, nodes_b, w_b, axes, area, par, point):
        nodes = np.zeros(8, np.int64)
        w = np.zeros(8)
        nodes[:len(nodes_a)] = nodes_a
        w[:len(w_a)] = w_a
        nodes[4:4 + len(nodes_b)] = nodes_b
        w[4:4 + len(w_b)] = w_b
        self.nodes.append(nodes)
        self.w.append(w)
        self.cnt.append((len(nodes_a), len(nodes_b)))
        self.axes.append(axes)
        self.area.append(area)
        self.par.append(par)
        self.point.append(point)

    def __len__(self):
        return len(self.area)

    def pack(self):
        n = len(self.area)
        return dict(
            nodes=np.array(self.nodes, np.int64).reshape(n, 8),
            cnt=np.array(self.cnt, np.int64).reshape(n, 2),
            w=np.array(self.w, float).reshape(n, 8),
            axes=np.array(self.axes, float).reshape(n, 9),
            area=np.array(self.area, float).reshape(n),
            par=np.array(self.par, float).reshape(n, K.N_JP),
            state=np.zeros((n, K.N_JS)),
            point=np.array(self.point, float).reshape(n, 3),
        )


def _face_point(axis, coord, P, Q):
    """The point (x, y, z) at (P, Q) of the plane x[axis] = coord, in the
    plane's coordinates (p, q) = (axis+1, axis+2) mod 3."""
    pt = np.zeros(3)
    pt[axis], pt[(axis + 1) % 3], pt[(axis + 2) % 3] = coord, P, Q
    return pt


def _axes(axis, sign):
    n = np.zeros(3)
    n[axis] = sign
    t1 = np.zeros(3)
    t1[(axis + 1) % 3] = 1.0
    t2 = np.cross(n, t1)
    return np.concatenate([n, t1, t2])


def _check_3(field_, value):
    v = np.asarray(value, float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise InputError(field_, f"must be 3 finite numbers, got {value!r}")
    return v


class Model:
    """A masonry micro-model under construction.

    Typical use::

        m = Model()
        m.add_box(lo, hi, cells, material)
        ...
        m.set_joints("coupled_softening", props)   # props or f(block_a, block_b)
        m.fix(m.select(lambda x: x[:, 2] < 1e-9), dofs=[2])
        m.add_strip("load", axis=1, coord=0.0, normal=-1, rect=..., kn=...)
    """

    def __init__(self):
        self.blocks = []
        self.n_nodes = 0
        self._x0 = []
        self.joint_law = None
        self.joint_props = None
        self.subcontact_refine = 1
        self.contacts = []
        self.strips = []
        self._strip_sc = _SubContacts()
        self._fixed = {}        # node -> {dof: velocity}
        self._fext = {}         # node -> force vector
        self._point_loads = []  # rigid blocks: (node, point, force)
        self._fixed_rotation = {}      # rigid block id -> {dof: angular velocity}
        self.large = False      # rigid blocks: large rotations
        self.monitors = []      # (name, nodes, direction)
        self.gravity = np.zeros(3)
        self._built = None

    # --- blocks ---------------------------------------------------------
    def add_box(self, lo, hi, cells, material, rigid=False):
        """A box block [lo, hi] with ``cells`` hexahedral cells per edge
        (each two overlays of 5 tetrahedra); a rigid box has no mesh, and
        ``cells`` sets the grid of its faces' sub-contacts."""
        bid = len(self.blocks)
        where = f"blocks[{bid}]"
        lo = _check_3(f"{where}.lo", lo)
        hi = _check_3(f"{where}.hi", hi)
        if np.any(hi - lo <= 0):
            raise InputError(f"{where}.size", f"box sizes must be positive, got {(hi - lo).tolist()}")
        cells = np.broadcast_to(np.asarray(cells), (3,))
        if not all(float(c).is_integer() and c >= 1 for c in cells):
            raise InputError(f"{where}.cells", f"cells per edge must be integers >= 1, got {cells.tolist()}")
        material.validate(f"{where}.material")
        cells = tuple(int(c) for c in cells)
        mesh = None if rigid else box_mesh(lo, hi, cells)
        return self._add(Block(bid, material, mesh, self.n_nodes, lo, hi, cells, bool(rigid)))

    def add_tet_block(self, nodes, tets, material):
        """An unstructured tetrahedral block (no joints are searched on it)."""
        bid = len(self.blocks)
        material.validate(f"blocks[{bid}].material")
        blk = Block(bid, material, tet_mesh(nodes, tets), self.n_nodes)
        return self._add(blk)

    def _add(self, blk):
        self.blocks.append(blk)
        self._x0.append(blk.centroid[None, :] if blk.rigid else blk.mesh.nodes)
        self.n_nodes += blk.n_nodes
        self._built = None
        return blk

    @property
    def rigid(self):
        """True if the blocks are rigid (all of them: see ``build``)."""
        return bool(self.blocks) and self.blocks[0].rigid

    @property
    def x0(self):
        return np.concatenate(self._x0) if self._x0 else np.zeros((0, 3))

    def select(self, predicate):
        """Global indices of block nodes whose coordinates satisfy
        ``predicate(x) -> bool array``."""
        return np.flatnonzero(predicate(self.x0))

    # --- joints ---------------------------------------------------------
    def set_joints(self, law, props, refine=1):
        """Joint law (by name) and properties: a JointProps for all joints,
        or a function (block_a, block_b) -> JointProps.  ``refine``: the
        sub-contacts sit at the gridpoints of a face grid refined that many
        times."""
        joint_law_id(law)
        if not (isinstance(refine, (int, np.integer)) and refine >= 1):
            raise InputError("joints.refine", f"must be an integer >= 1, got {refine!r}")
        self.joint_law = law
        self.joint_props = props
        self.subcontact_refine = int(refine)
        self._built = None

    def _find_contacts(self, sc):
        boxes = [b for b in self.blocks if b.is_box]
        self.contacts = []
        for i, b1 in enumerate(boxes):
            for b2 in boxes[i + 1:]:
                for axis in range(3):
                    for lower, upper in ((b1, b2), (b2, b1)):
                        if abs(lower.hi[axis] - upper.lo[axis]) > GEOM_TOL:
                            continue
                        p, q = lower.face_axes(axis)
                        rect = ((max(lower.lo[p], upper.lo[p]), min(lower.hi[p], upper.hi[p])),
                                (max(lower.lo[q], upper.lo[q]), min(lower.hi[q], upper.hi[q])))
                        if min(rect[0][1] - rect[0][0], rect[1][1] - rect[1][0]) <= GEOM_TOL:
                            continue
                        self._add_contact(sc, lower, upper, axis, rect)

    def _add_contact(self, sc, lower, upper, axis, rect):
        cid = len(self.contacts)
        # sub-contacts on the finer face (more gridpoints in the overlap)
        if upper.nodes_in_rect(axis, rect) > lower.nodes_in_rect(axis, rect):
            a, b, side_a, side_b, sign = upper, lower, 0, 1, -1.0
        else:
            a, b, side_a, side_b, sign = lower, upper, 1, 0, 1.0
        props = self.joint_props(a, b) if callable(self.joint_props) else self.joint_props
        if not isinstance(props, JointProps):
            raise InputError("joints.props", f"expected JointProps, got {type(props).__name__}")
        props.validate(f"joints[{cid}] (blocks {a.id}-{b.id})", self.joint_law)
        row = props.row()
        axes = _axes(axis, sign)
        start = len(sc)
        P, Q, A = a.face_points(axis, rect, self.subcontact_refine)
        for pp, qq, ar in zip(P, Q, A):
            na, wa = a.interpolate(axis, side_a, pp, qq)
            nb, wb = b.interpolate(axis, side_b, pp, qq)
            sc.add(na, wa, nb, wb, axes, ar, row, _face_point(axis, lower.hi[axis], pp, qq))
        self.contacts.append(Contact(cid, a.id, b.id, axis, axes[:3].copy(), float(A.sum()),
                                     slice(start, len(sc)), props))

    # --- boundary conditions ---------------------------------------------
    def _faces_on_plane(self, axis, coord, normal):
        """(block, side) of the box faces lying on the plane x[axis] = coord
        whose outward normal is ``normal`` (+1 or -1) times e_axis."""
        if normal not in (1, -1):
            raise InputError("normal", f"must be +1 or -1, got {normal!r}")
        out = []
        for b in self.blocks:
            if not b.is_box:
                continue
            side = 1 if normal > 0 else 0
            face = b.hi[axis] if side else b.lo[axis]
            if abs(face - coord) <= GEOM_TOL:
                out.append((b, side))
        return out

    def _face_rect(self, b, axis, rect):
        p, q = b.face_axes(axis)
        r = ((max(b.lo[p], rect[0][0]), min(b.hi[p], rect[0][1])),
             (max(b.lo[q], rect[1][0]), min(b.hi[q], rect[1][1])))
        if min(r[0][1] - r[0][0], r[1][1] - r[1][0]) <= GEOM_TOL:
            return None
        return r

    def add_strip(self, name, axis, coord, normal, rect, kn, velocity=(0.0, 0.0, 0.0)):
        """A rigid bearing strip on the plane x[axis] = coord, covering
        ``rect`` = ((plo, phi), (qlo, qhi)) in the plane's coordinates
        (p, q) = (axis+1, axis+2) mod 3, bearing on the block faces whose
        outward normal is ``normal`` * e_axis.  Moves with ``velocity``.
        Its node follows the block nodes; its number is set by ``build``."""
        where = f"strips.{name}"
        if kn is None or not np.isfinite(kn) or kn <= 0:
            raise InputError(f"{where}.kn", f"must be a positive stiffness, got {kn!r}")
        velocity = _check_3(f"{where}.velocity", velocity)
        index = len(self.strips)
        row = np.zeros(K.N_JP)
        row[K.JP_KN] = kn
        axes = _axes(axis, float(normal))
        points = []
        for b, side in self._faces_on_plane(axis, coord, normal):
            r = self._face_rect(b, axis, rect)
            if r is not None:
                points += [(b.interpolate(axis, side, pp, qq), ar, _face_point(axis, coord, pp, qq))
                           for pp, qq, ar in zip(*b.face_points(axis, r, self.subcontact_refine))]
        if not points:
            raise InputError(f"{where}.rect", "the strip touches no block face")
        start = len(self._strip_sc)
        for (na, wa), ar, pt in points:     # side B: the strip, -(index + 1) until build
            self._strip_sc.add(na, wa, [-(index + 1)], [1.0], axes, ar, row, pt)
        strip = Strip(name, -1, axis, int(normal), float(kn), slice(start, len(self._strip_sc)),
                      float(sum(p[1] for p in points)))
        strip.velocity = velocity
        p, q = (axis + 1) % 3, (axis + 2) % 3
        strip.x0 = np.zeros(3)
        strip.x0[axis], strip.x0[p], strip.x0[q] = coord, np.mean(rect[0]), np.mean(rect[1])
        self.strips.append(strip)
        self._built = None
        return strip

    def add_pressure(self, axis, coord, normal, rect, pressure):
        """A uniform pressure (Pa, positive = compressive, acting against the
        outward normal) on the block faces of the plane x[axis] = coord with
        outward normal ``normal`` * e_axis, within ``rect``; lumped to the
        face gridpoints with their tributary areas."""
        if not np.isfinite(pressure):
            raise InputError("pressure", f"must be finite, got {pressure!r}")
        total = 0.0
        for b, side in self._faces_on_plane(axis, coord, normal):
            r = self._face_rect(b, axis, rect)
            if r is None:
                continue
            P, Q, A = b.face_points(axis, r)
            for pp, qq, ar in zip(P, Q, A):
                force = np.zeros(3)
                force[axis] = -normal * pressure * ar
                if b.rigid:
                    self._point_loads.append((b.node0, _face_point(axis, coord, pp, qq), force))
                    total += ar
                    continue
                nodes, ws = b.interpolate(axis, side, pp, qq)
                for nd, wgt in zip(nodes, ws):
                    f = self._fext.setdefault(nd, np.zeros(3))
                    f += wgt * force
                total += ar
        if total == 0.0:
            raise InputError("pressure.rect", "the pressure acts on no block face")
        self._built = None
        return total

    def add_force(self, nodes, force):
        """A constant force (N) on each of ``nodes``."""
        force = _check_3("force", force)
        for nd in np.atleast_1d(nodes):
            f = self._fext.setdefault(int(nd), np.zeros(3))
            f += force
        self._built = None

    def fix(self, nodes, dofs=(0, 1, 2), velocity=0.0):
        """Prescribes the velocity of components ``dofs`` of ``nodes``."""
        nodes = np.atleast_1d(np.asarray(nodes, np.int64))
        if nodes.size == 0:
            raise InputError("fix.nodes", "no node selected")
        if np.any((nodes < 0) | (nodes >= self.n_nodes)):
            raise InputError("fix.nodes", "node index out of range")
        vel = np.broadcast_to(np.asarray(velocity, float), (len(dofs),))
        for nd in nodes:
            d = self._fixed.setdefault(int(nd), {})
            for dof, vv in zip(dofs, vel):
                if dof not in (0, 1, 2):
                    raise InputError("fix.dofs", f"dofs are 0, 1, 2, got {dof!r}")
                d[dof] = float(vv)
        self._built = None

    def fix_rotation(self, block, dofs=(0, 1, 2), velocity=0.0):
        """Prescribes the angular velocity (rad per unit time, about the
        global axes ``dofs``) of a rigid block; zero holds those rotations
        (its translations: ``fix`` on ``block.node0``)."""
        if not block.rigid:
            raise InputError(f"blocks[{block.id}].fix_rotation", "only a rigid block has rotations")
        vel = np.broadcast_to(np.asarray(velocity, float), (len(dofs),))
        d = self._fixed_rotation.setdefault(block.id, {})
        for dof, w in zip(dofs, vel):
            if dof not in (0, 1, 2):
                raise InputError(f"blocks[{block.id}].fix_rotation.dofs", f"dofs are 0, 1, 2, got {dof!r}")
            d[dof] = float(w)
        self._built = None

    def add_monitor(self, name, nodes, direction):
        """Records, every step, the reaction (sum over ``nodes`` of the force
        the constraint applies, along ``direction``) and the mean
        displacement of ``nodes`` along ``direction``.  ``nodes``: node
        indices, or Strip objects (their nodes are numbered at build)."""
        if direction not in (0, 1, 2):
            raise InputError(f"monitors.{name}.direction", f"must be 0, 1 or 2, got {direction!r}")
        items = list(nodes) if np.ndim(nodes) else [nodes]
        if not items:
            raise InputError(f"monitors.{name}.nodes", "no node selected")
        self.monitors.append((name, items, int(direction)))
        self._built = None

    # --- assembly --------------------------------------------------------
    def build(self):
        """Packs the model into flat arrays (cached until the model changes)."""
        if self._built is not None:
            return self._built
        if not self.blocks:
            raise InputError("blocks", "the model has no block")
        if len({b.rigid for b in self.blocks}) > 1:
            raise InputError("physics.blocks", "a model's blocks are all rigid or all deformable, not both")
        if self.large and not self.rigid:
            raise InputError("physics.displacements", "large displacements need rigid blocks: deformable "
                             "blocks are small-displacement (strains on the initial geometry)")
        if self.rigid:
            self._built = self._build_rigid()
            return self._built
        nb = self.n_nodes
        nn = nb + len(self.strips)
        x0 = np.zeros((nn, 3))
        x0[:nb] = self.x0
        tets, dn, vol, wt, zp, gptr, gnodes, gnptr, block_of_node = [], [], [], [], [], [0], [], [0], []
        t_off = 0
        for b in self.blocks:
            m = b.mesh
            t = m.tets + b.node0
            try:
                d, v = tet_geometry(x0, t)
            except InputError as e:
                raise InputError(f"blocks[{b.id}].mesh", e.reason) from None
            tets.append(t)
            dn.append(d)
            vol.append(v)
            wt.append(m.weight)
            zp.append(np.tile(b.material.row(), (t.shape[0], 1)))
            gptr.extend((m.gptr[1:] + t_off).tolist())
            gnodes.append(m.gnodes + b.node0)
            gnptr.extend((m.gnptr[1:] + (gnptr[-1])).tolist())
            block_of_node.append(np.full(b.n_nodes, b.id))
            t_off += t.shape[0]
        # one zone law for the model: elastic rows never yield under MC
        zlaw = max(b.material.law_id for b in self.blocks)
        common = self._pack_common(x0)
        joints, bearings = common["joints"], common["bearings"]
        fext = np.zeros((nn, 3))
        for nd, f in self._fext.items():
            fext[nd] += f
        vol = np.concatenate(vol)
        wt = np.concatenate(wt)
        tets = np.concatenate(tets)
        rho = np.concatenate([np.full(b.mesh.tets.shape[0], b.material.density) for b in self.blocks])
        mphys = np.zeros(nn)
        np.add.at(mphys, tets.ravel(), np.repeat(rho * vol * wt / 4.0, 4))
        stiff = np.zeros(nn)
        zp = np.concatenate(zp)
        dn = np.concatenate(dn)
        _zone_stiffness(stiff, tets, dn, vol * wt, zp)
        _contact_stiffness(stiff, joints)
        _contact_stiffness(stiff, bearings)
        self._built = dict(
            common, rigid=False, zlaw=zlaw,
            tets=tets, dn=dn, vol=vol, wt=wt, zp=zp,
            gptr=np.asarray(gptr, np.int64), gnodes=np.concatenate(gnodes),
            gnptr=np.asarray(gnptr, np.int64), fext=fext,
            mphys=mphys, stiffness=stiff,
            block_of_node=np.concatenate(block_of_node + [np.full(len(self.strips), -1)]),
        )
        return self._built

    def _pack_common(self, x0):
        """What deformable and rigid models share: the joints (sub-contacts
        found from the initial geometry) and the strips' bearings, with the
        strips numbered after the block nodes; fixities; monitors."""
        nb, nn = self.n_nodes, x0.shape[0]
        sc = _SubContacts()
        self.contacts = []
        if self.joint_law is not None:
            self._find_contacts(sc)
        joints = sc.pack()
        bearings = self._strip_sc.pack()
        strip_side = bearings["nodes"][:, 4]
        bearings["nodes"][:, 4] = np.where(strip_side < 0, nb - strip_side - 1, strip_side)
        for i, s in enumerate(self.strips):
            s.node = nb + i
        fixed = np.zeros((nn, 3), np.uint8)
        vpres = np.zeros((nn, 3))
        for nd, dd in self._fixed.items():
            for dof, vv in dd.items():
                fixed[nd, dof] = 1
                vpres[nd, dof] = vv
        for s in self.strips:
            x0[s.node] = s.x0
            fixed[s.node] = 1
            vpres[s.node] = s.velocity
        mon_nodes, mon_dir, mon_grp = [], [], []
        for g, (_, items, d) in enumerate(self.monitors):
            nodes = [it.node if isinstance(it, Strip) else int(it) for it in items]
            mon_nodes.extend(nodes)
            mon_dir.extend([d] * len(nodes))
            mon_grp.extend([g] * len(nodes))
        return dict(nn=nn, x0=x0, jlaw=joint_law_id(self.joint_law) if self.joint_law else K.JOINT_ELASTIC,
                    joints=joints, bearings=bearings, fixed=fixed, vpres=vpres,
                    mon_nodes=np.asarray(mon_nodes, np.int64), mon_dir=np.asarray(mon_dir, np.int64),
                    mon_grp=np.asarray(mon_grp, np.int64))

    def _build_rigid(self):
        """Rigid blocks: per body (the blocks, then the strips) its mass and
        principal inertia (a box: m (b^2 + c^2) / 12 about each axis), lever
        scale (half the diagonal) and the Gershgorin bounds of its
        translational and rotational contact stiffness; per sub-contact the
        two bodies and the levers (from each body's centroid to the point,
        in the body frame = global at the start); point loads with their
        levers.  No zone arrays."""
        nb = self.n_nodes
        x0 = np.zeros((nb + len(self.strips), 3))
        x0[:nb] = self.x0
        common = self._pack_common(x0)
        nn = common["nn"]
        mphys = np.zeros(nn)
        inertia = np.ones((nn, 3))
        rlen = np.ones(nn)
        for b in self.blocks:
            size = b.hi - b.lo
            m = b.material.density * float(np.prod(size))
            mphys[b.node0] = m
            inertia[b.node0] = m / 12.0 * (np.sum(size ** 2) - size ** 2)
            rlen[b.node0] = 0.5 * float(np.linalg.norm(size))
        rfixed = np.zeros((nn, 3), np.uint8)
        rfixed[nb:] = 1
        ompres = np.zeros((nn, 3))
        for bid, dd in self._fixed_rotation.items():
            for dof, w in dd.items():
                rfixed[self.blocks[bid].node0, dof] = 1
                ompres[self.blocks[bid].node0, dof] = w
        kt, kr = np.zeros(nn), np.zeros(nn)
        for key in ("joints", "bearings"):
            sc = common[key]
            sc["body"] = sc["nodes"][:, [0, 4]].copy()
            sc["lever"] = sc["point"][:, None, :] - x0[sc["body"]]          # (n, 2, 3)
            _rigid_contact_stiffness(kt, kr, sc)
        loads = self._point_loads + [(nd, x0[nd], f) for nd, f in self._fext.items()]
        return dict(
            common, rigid=True, large=int(self.large), mphys=mphys, inertia=inertia, rlen=rlen,
            rfixed=rfixed, ompres=ompres, stiffness=kt, rot_stiffness=kr,
            pl_body=np.array([nd for nd, _, _ in loads], np.int64),
            pl_lever=np.array([p - x0[nd] for nd, p, _ in loads], float).reshape(-1, 3),
            pl_force=np.array([f for _, _, f in loads], float).reshape(-1, 3),
            block_of_node=np.concatenate([np.arange(nb), np.full(len(self.strips), -1)]),
        )


def _zone_stiffness(stiff, tets, dn, wvol, zp, chunk=20000):
    """Adds, per node, a Gershgorin bound of the zones' stiffness: the largest
    absolute row sum (over the node's 3 rows) of the element matrices
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
        rows = np.abs(ke).sum(axis=2).reshape(n, 4, 3).max(axis=2)       # (n, 4)
        np.add.at(stiff, t.ravel(), rows.ravel())


def _contact_rowmax(sc):
    """Per sub-contact: area times the largest absolute row sum of its
    stiffness C = k_n n n^T + k_s (t1 t1^T + t2 t2^T)."""
    n = sc["area"].shape[0]
    ax = sc["axes"].reshape(n, 3, 3)
    kn, ks = sc["par"][:, K.JP_KN], sc["par"][:, K.JP_KS]
    C = (kn[:, None, None] * np.einsum("ni,nj->nij", ax[:, 0], ax[:, 0])
         + ks[:, None, None] * (np.einsum("ni,nj->nij", ax[:, 1], ax[:, 1])
                                + np.einsum("ni,nj->nij", ax[:, 2], ax[:, 2])))
    return np.abs(C).sum(axis=2).max(axis=1) * sc["area"]


def _rigid_contact_stiffness(kt, kr, sc):
    """Gershgorin bounds of the contact stiffness of rigid bodies, for any
    orientation: a sub-contact of stiffness matrix C (as in
    ``_contact_stiffness``, absolute row sums at most c) between bodies with
    levers r_A, r_B couples their velocities through G = [I, -[r]x]; the
    rows of the 12 x 12 block G^T C G sum, in absolute value, to at most
    c (2 + sqrt2 (|r_A| + |r_B|)) for a translation and
    c |r| (2 sqrt2 + 2 |r_A| + 2 |r_B|) for a rotation of the body with
    lever r (|[r]x| has row sums at most sqrt2 |r|)."""
    if sc["area"].shape[0] == 0:
        return
    c = _contact_rowmax(sc)
    r = np.linalg.norm(sc["lever"], axis=2)                  # (n, 2)
    rsum = r.sum(axis=1)
    s2 = math.sqrt(2.0)
    for side in range(2):
        np.add.at(kt, sc["body"][:, side], c * (2.0 + s2 * rsum))
        np.add.at(kr, sc["body"][:, side], c * r[:, side] * (2.0 * s2 + 2.0 * rsum))


def _contact_stiffness(stiff, sc):
    """Gershgorin bound of the sub-contacts' stiffness: a sub-contact couples
    its (up to 8) interpolated nodes through
    C = area (k_n n n^T + k_s (t1 t1^T + t2 t2^T)); node i's absolute row sum
    is |w_i| (sum_j |w_j|) max_row sum |C|."""
    if sc["area"].shape[0] == 0:
        return
    rowmax = _contact_rowmax(sc)
    w = np.abs(sc["w"])
    wsum = w.sum(axis=1)
    np.add.at(stiff, sc["nodes"].ravel(), (w * (wsum * rowmax)[:, None]).ravel())
