"""A masonry micro-model under construction: blocks, joint settings,
boundary conditions (fixities, forces, pressures, bearing strips) and
monitors.  ``Model.build`` packs it for the solver (assembly.py).

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
import numpy as np

from .assembly import assemble
from .blocks import RULES, Block, check_3, face_point, face_quadrature, refine_axes
from .contacts import SubContacts, bearing_strip, faces_on_plane
from .elements import ELEMENTS
from ..errors import InputError
from .laws import Elastic, joint_law
from .mesh import box_mesh, tet_mesh


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
        self.joint_law, self.joint_props, self.joint_rule = None, None, "simpson"
        self.joint_refine = (1, 1, 1)
        self.strip_refine = (1, 1, 1)
        self.strips = []
        self.strip_subcontacts = SubContacts()
        self.fixities = {}           # node -> {dof: velocity}
        self.forces = {}             # node -> force vector
        self.point_loads = []        # rigid blocks: (node, point, force)
        self.rotation_fixities = {}  # rigid block id -> {dof: angular velocity}
        self.large = False           # rigid blocks: large rotations
        self.monitors = []           # (name, nodes, direction)
        self.gravity = np.zeros(3)

    # --- blocks ---------------------------------------------------------
    def add_box(self, lo, hi, cells, material, rigid=False, element="zones"):
        """A box block [lo, hi] with ``cells`` hexahedral cells per edge
        (each two overlays of 5 tetrahedra); a rigid box has no mesh, and
        ``cells`` sets the grid of its faces' sub-contacts.  ``element``:
        'zones' (each tetrahedron a zone with its own stress and law) or,
        for an elastic block, a cell computed as one matrix
        (elements.ELEMENTS: 'tet10' the same cell, 'hex8i' exact in
        bending)."""
        bid = len(self.blocks)
        where = f"blocks[{bid}]"
        lo = check_3(f"{where}.lo", lo)
        hi = check_3(f"{where}.hi", hi)
        if np.any(hi - lo <= 0):
            raise InputError(f"{where}.size", f"box sizes must be positive, got {(hi - lo).tolist()}")
        cells = np.broadcast_to(np.asarray(cells), (3,))
        if not all(float(c).is_integer() and c >= 1 for c in cells):
            raise InputError(f"{where}.cells", f"cells per edge must be integers >= 1, got {cells.tolist()}")
        material.validate(f"{where}.material")
        if element != "zones" and (element not in ELEMENTS or type(material) is not Elastic):
            raise InputError(f"{where}.element", f"must be 'zones' or, for an elastic block, one of "
                             f"{', '.join(ELEMENTS)}; got {element!r} for {type(material).__name__}")
        cells = tuple(int(c) for c in cells)
        mesh = None if rigid else box_mesh(lo, hi, cells)
        return self._add(Block(bid, material, mesh, self.n_nodes, lo, hi, cells, bool(rigid), element))

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
    def set_joints(self, law, props, refine=1, strip_refine=None, rule="simpson"):
        """Joint law (by name, laws.JOINT_LAWS) and properties: a JointProps
        for all joints, or a function (block_a, block_b) -> JointProps.
        ``refine``: each interval of the union of both faces' cell grids is
        split that many times (one integer, or one per global axis x, y, z),
        and the sub-contacts sit at the points of ``rule`` on it (composite
        Simpson, or 'vertices': blocks.face_quadrature); or a function
        (block_a, block_b) -> such a refinement.  Strips added afterwards
        take ``strip_refine`` (default: ``refine``, or 1 for a function)."""
        joint_law(law)
        if strip_refine is None:
            strip_refine = 1 if callable(refine) else refine
        if rule not in RULES:
            raise InputError("joints.rule", f"must be one of {', '.join(RULES)}, got {rule!r}")
        self.joint_law, self.joint_rule, self.joint_props = law, rule, props
        self.joint_refine = refine if callable(refine) else refine_axes(refine, "joints.refine")
        self.strip_refine = refine_axes(strip_refine, "strips.refine")

    # --- boundary conditions ---------------------------------------------
    def add_strip(self, name, axis, coord, normal, rect, kn, velocity=(0.0, 0.0, 0.0), turns=False, force=None,
                  friction=0.0):
        """A rigid bearing strip on the plane x[axis] = coord, covering
        ``rect`` = ((plo, phi), (qlo, qhi)) in the plane's coordinates
        (p, q) = (axis+1, axis+2) mod 3, bearing on the block faces whose
        outward normal is ``normal`` * e_axis.  Moves with ``velocity``;
        ``turns``: about its rectangle's long side (a roller); ``force``:
        held by it along its normal (a platen); ``friction``: its Coulomb
        coefficient.  Nodes: ``Assembly.strip_nodes``, ``turn_nodes``."""
        turn_index = sum(s.turn >= 0 for s in self.strips) if turns else -1
        strip = bearing_strip(self.strip_subcontacts, self.blocks, len(self.strips), name, axis, coord, normal, rect,
                              kn, velocity, self.strip_refine, turn_index, friction)
        if force is not None:
            strip.free, strip.force = (axis,), check_3(f"strips.{name}.force", force)
        self.strips.append(strip)
        return strip

    def add_pressure(self, axis, coord, normal, rect, pressure):
        """A uniform pressure (Pa, positive = compressive, acting against the
        outward normal) on the block faces of the plane x[axis] = coord with
        outward normal ``normal`` * e_axis, within ``rect``; integrated by
        the composite Simpson rule on the face grids (blocks.face_quadrature),
        each point's force shared by the face's nodes with its bilinear
        weights."""
        if not np.isfinite(pressure):
            raise InputError("pressure", f"must be finite, got {pressure!r}")
        total = 0.0
        for b, side, r in faces_on_plane(self.blocks, axis, coord, normal, rect):
            P, Q, A = face_quadrature(r, zip(b.face_grid(axis)))
            for pp, qq, ar in zip(P, Q, A):
                force = np.zeros(3)
                force[axis] = -normal * pressure * ar
                total += ar
                if b.rigid:
                    self.point_loads.append((b.node0, face_point(axis, coord, pp, qq), force))
                    continue
                nodes, ws = b.interpolate(axis, side, pp, qq)
                for nd, wgt in zip(nodes, ws):
                    f = self.forces.setdefault(nd, np.zeros(3))
                    f += wgt * force
        if total == 0.0:
            raise InputError("pressure.rect", "the pressure acts on no block face")
        return total

    def add_force(self, nodes, force):
        """A constant force (N) on each of ``nodes``."""
        force = check_3("force", force)
        for nd in np.atleast_1d(nodes):
            f = self.forces.setdefault(int(nd), np.zeros(3))
            f += force

    def fix(self, nodes, dofs=(0, 1, 2), velocity=0.0):
        """Prescribes the velocity of components ``dofs`` of ``nodes``."""
        nodes = np.atleast_1d(np.asarray(nodes, np.int64))
        if nodes.size == 0:
            raise InputError("fix.nodes", "no node selected")
        if np.any((nodes < 0) | (nodes >= self.n_nodes)):
            raise InputError("fix.nodes", "node index out of range")
        vel = np.broadcast_to(np.asarray(velocity, float), (len(dofs),))
        for nd in nodes:
            d = self.fixities.setdefault(int(nd), {})
            for dof, vv in zip(dofs, vel):
                if dof not in (0, 1, 2):
                    raise InputError("fix.dofs", f"dofs are 0, 1, 2, got {dof!r}")
                d[dof] = float(vv)

    def fix_rotation(self, block, dofs=(0, 1, 2), velocity=0.0):
        """Prescribes the angular velocity (rad per unit time, about the
        global axes ``dofs``) of a rigid block; zero holds those rotations
        (its translations: ``fix`` on ``block.node0``)."""
        if not block.rigid:
            raise InputError(f"blocks[{block.id}].fix_rotation", "only a rigid block has rotations")
        vel = np.broadcast_to(np.asarray(velocity, float), (len(dofs),))
        d = self.rotation_fixities.setdefault(block.id, {})
        for dof, w in zip(dofs, vel):
            if dof not in (0, 1, 2):
                raise InputError(f"blocks[{block.id}].fix_rotation.dofs", f"dofs are 0, 1, 2, got {dof!r}")
            d[dof] = float(w)

    def add_monitor(self, name, nodes, direction):
        """Records, every step, the reaction (sum over ``nodes`` of the force
        the constraint applies, along ``direction``) and the mean
        displacement of ``nodes`` along ``direction``.  ``nodes``: node
        indices, or Strip objects (their nodes: ``Assembly.strip_nodes``)."""
        if direction not in (0, 1, 2):
            raise InputError(f"monitors.{name}.direction", f"must be 0, 1 or 2, got {direction!r}")
        items = list(nodes) if np.ndim(nodes) else [nodes]
        if not items:
            raise InputError(f"monitors.{name}.nodes", "no node selected")
        self.monitors.append((name, items, int(direction)))

    # --- assembly --------------------------------------------------------
    def build(self):
        """The model packed for the solver (assembly.Assembly); each call
        packs it anew."""
        return assemble(self)
