"""Assembly: a Model packed into the kernels' containers (``Model.build``).

Deformable blocks: nodes (the blocks' gridpoints, then one per strip,
then a second one per strip that turns),
zones, joints and the strips' bearings, the Gershgorin bound of each
node's stiffness.  Rigid blocks: one body per block (then one per strip),
with its mass, principal inertia, lever scale and the bounds of its
translational and rotational contact stiffness; no zones.
"""
from dataclasses import dataclass

import numpy as np

from . import kernels as K
from .contacts import Strip, SubContacts, find_joints, with_gather
from ..errors import InputError
from .laws import joint_law
from .elements import cell_stiffness
from .mesh import tet_geometry
from .stability import cell_stiffness_bound, contact_stiffness, rigid_contact_stiffness, zone_stiffness


@dataclass
class Assembly:
    """What the solver needs of a model.  The containers hold the model's
    arrays; their state arrays (displacements, stresses, tractions) are
    zero, and each solver works on copies of them."""
    rigid: bool
    large: bool
    zlaw: int
    jlaw: int
    nodes: K.Nodes
    zones: K.Zones
    cells: K.Cells
    joints: K.Contacts
    bearings: K.Contacts
    bodies: K.Bodies
    monitors: K.Monitors
    joint_points: np.ndarray      # (n, 3) position of each joint sub-contact
    bearing_points: np.ndarray
    contacts: list                # contacts.Contact, one per joint
    stiffness: np.ndarray         # (n, 3) bound of each node's (body's translational) stiffness, per component
    rot_stiffness: np.ndarray     # (n,) rigid: bound of each body's rotational stiffness
    inertia: np.ndarray           # (n, 3) rigid: principal moments of inertia
    h_min: float                  # smallest zone, cell or body size (the divergence guard)
    block_of_node: np.ndarray     # (n,) block of each node (-1: a strip)
    blocks: tuple                 # blocks.Block, as the model added them
    zone_ptr: np.ndarray          # (blocks + 1,) the zones of block b: zone_ptr[b]:zone_ptr[b + 1]
    cell_ptr: np.ndarray          # (blocks + 1,) its linear cells: cell_ptr[b]:cell_ptr[b + 1]
    strips: tuple                 # contacts.Strip
    strip_nodes: np.ndarray       # (strips,) the node of each strip (after the block nodes)
    turn_nodes: np.ndarray        # deformable: (strips that turn,) the second node of each (after the strips')
    monitor_names: tuple          # the name of each monitor group
    gravity: np.ndarray           # (3,) m/s^2

    @property
    def n(self):
        return self.nodes.x0.shape[0]

    def monitor(self, name):
        """The group number of the monitor named ``name``."""
        if name not in self.monitor_names:
            raise InputError("monitor", f"no monitor named {name!r}")
        return self.monitor_names.index(name)


def assemble(model):
    """Packs ``model`` (blocks all rigid or all deformable)."""
    if not model.blocks:
        raise InputError("blocks", "the model has no block")
    if len({b.rigid for b in model.blocks}) > 1:
        raise InputError("physics.blocks", "a model's blocks are all rigid or all deformable, not both")
    if model.large and not model.rigid:
        raise InputError("physics.displacements", "large displacements need rigid blocks: deformable "
                         "blocks are small-displacement (strains on the initial geometry)")
    nb = model.n_nodes
    x0 = np.zeros((nb + len(model.strips) + (0 if model.rigid else _turning(model)), 3))
    x0[:nb] = model.x0
    common = _common(model, x0)
    maps = _index_maps(model)
    return _rigid(model, x0, maps, **common) if model.rigid else _deformable(model, x0, maps, **common)


def _turning(model):
    """The number of strips that turn."""
    return sum(s.turn >= 0 for s in model.strips)


def _index_maps(model):
    """What the assembly's users look up by block, strip or monitor: the
    blocks, each block's zones and cells, the strips and their nodes, the
    monitors' names, gravity."""
    nz = [b.mesh.tets.shape[0] if b.element == "zones" and not b.rigid else 0 for b in model.blocks]
    nc = [b.mesh.cells.shape[0] if b.element != "zones" and not b.rigid else 0 for b in model.blocks]
    return dict(blocks=tuple(model.blocks), zone_ptr=np.concatenate([[0], np.cumsum(nz)]).astype(np.int64),
                cell_ptr=np.concatenate([[0], np.cumsum(nc)]).astype(np.int64), strips=tuple(model.strips),
                strip_nodes=model.n_nodes + np.arange(len(model.strips), dtype=np.int64),
                turn_nodes=model.n_nodes + len(model.strips) + np.arange(0 if model.rigid else _turning(model),
                                                                         dtype=np.int64),
                monitor_names=tuple(name for name, _, _ in model.monitors),
                gravity=np.asarray(model.gravity, float).copy())


def _common(model, x0):
    """What deformable and rigid models share: the joints (sub-contacts
    found from the initial geometry) and the strips' bearings, with the
    strips numbered after the block nodes; fixities; monitors."""
    nb, nn = model.n_nodes, x0.shape[0]
    contacts, sc = [], SubContacts()
    if model.joint_law is not None:
        contacts, sc = find_joints(model.blocks, model.joint_law, model.joint_props, model.joint_refine,
                                   model.joint_rule)
    joints, joint_points = sc.pack()
    bearings, bearing_points = model.strip_subcontacts.pack()
    strip_side = bearings.nodes[:, 4]
    bearings.nodes[:, 4] = np.where(strip_side < 0, nb - strip_side - 1, strip_side)
    turn_side = bearings.nodes[:, 5]
    bearings.nodes[:, 5] = np.where(turn_side < 0, nb + len(model.strips) - turn_side - 1, turn_side)
    joints, bearings = with_gather(joints, nn), with_gather(bearings, nn)
    fixed = np.zeros((nn, 3), np.uint8)
    vpres = np.zeros((nn, 3))
    for nd, dd in model.fixities.items():
        for dof, vv in dd.items():
            fixed[nd, dof] = 1
            vpres[nd, dof] = vv
    for s in model.strips:
        x0[nb + s.index] = s.x0
        fixed[nb + s.index] = 1
        fixed[nb + s.index, list(s.free)] = 0
        vpres[nb + s.index] = s.velocity
        if s.turn >= 0 and not model.rigid:     # its second node moves along the strip's normal only
            x0[nb + len(model.strips) + s.turn_index] = s.x0
            fixed[nb + len(model.strips) + s.turn_index] = 1
            fixed[nb + len(model.strips) + s.turn_index, s.axis] = 0
    mon_nodes, mon_dir, mon_grp = [], [], []
    for g, (_, items, d) in enumerate(model.monitors):
        nodes = [nb + it.index if isinstance(it, Strip) else int(it) for it in items]
        mon_nodes.extend(nodes)
        mon_dir.extend([d] * len(nodes))
        mon_grp.extend([g] * len(nodes))
    monitors = K.Monitors(np.asarray(mon_nodes, np.int64), np.asarray(mon_dir, np.int64),
                          np.asarray(mon_grp, np.int64))
    jlaw = joint_law(model.joint_law).id if model.joint_law else K.JOINT_ELASTIC
    return dict(jlaw=jlaw, joints=joints, bearings=bearings, joint_points=joint_points,
                bearing_points=bearing_points, contacts=contacts, fixed=fixed, vpres=vpres, monitors=monitors)


def _nodes(x0, mphys, fixed, vpres, fext):
    nn = x0.shape[0]
    return K.Nodes(x0=x0, u=np.zeros((nn, 3)), v=np.zeros((nn, 3)), f=np.zeros((nn, 3)), mass=np.ones((nn, 3)),
                   mgrav=mphys, fixed=fixed, vpres=vpres, fext=fext)


def _deformable(model, x0, maps, jlaw, joints, bearings, joint_points, bearing_points, contacts, fixed, vpres, monitors):
    """Zones of the blocks meshed into zones, cells of the blocks computed
    as linear cells, nodal masses for gravity (a quarter of each
    tetrahedron's weighted mass, an eighth of each cell's), the nodes'
    stiffness bounds."""
    nn = x0.shape[0]
    zb = [b for b in model.blocks if b.element == "zones"]
    zones = _zones(zb, x0) if zb else K.empty_zones()
    cells = _cells([b for b in model.blocks if b.element != "zones"])
    # one zone law for the model: elastic rows never yield under Mohr-Coulomb
    zlaw = max(b.material.law_id for b in zb) if zb else K.ZONE_NONE
    fext = np.zeros((nn, 3))
    for nd, f in model.forces.items():
        fext[nd] += f
    for s in model.strips:
        if s.force is not None:
            fext[model.n_nodes + s.index] += s.force
    mphys = np.zeros(nn)
    stiff = np.zeros((nn, 3))
    if zb:
        rho = np.concatenate([np.full(b.mesh.tets.shape[0], b.material.density) for b in zb])
        np.add.at(mphys, zones.tets.ravel(), np.repeat(rho * zones.vol * zones.wt / 4.0, 4))
        zone_stiffness(stiff, zones.tets, zones.dn, zones.vol * zones.wt, zones.par)
    if cells.nodes.shape[0]:
        np.add.at(mphys, cells.nodes.ravel(), np.repeat(cell_masses(model.blocks, cells), 8))
        cell_stiffness_bound(stiff, cells)
    contact_stiffness(stiff, joints)
    contact_stiffness(stiff, bearings)
    sizes = [np.cbrt(6.0 * zones.vol)] + [np.full(1, min((b.hi - b.lo) / b.cells)) for b in model.blocks
                                           if b.element != "zones"]
    return Assembly(
        rigid=False, large=False, zlaw=zlaw, jlaw=jlaw, nodes=_nodes(x0, mphys, fixed, vpres, fext), zones=zones,
        cells=cells, joints=joints, bearings=bearings, bodies=K.empty_bodies(), monitors=monitors,
        joint_points=joint_points, bearing_points=bearing_points, contacts=contacts, stiffness=stiff,
        rot_stiffness=np.zeros(0), inertia=np.zeros((0, 3)), h_min=float(np.min(np.concatenate(sizes))),
        block_of_node=np.concatenate([np.full(b.n_nodes, b.id) for b in model.blocks]
                                     + [np.full(nn - model.n_nodes, -1)]), **maps)


def _zones(blocks, x0):
    """The zones (tetrahedra and their mixed-discretization groups) of
    ``blocks``, with their laws' parameter rows."""
    tets, dn, vol, wt, zp, gptr, gnodes, gnptr = [], [], [], [], [], [0], [], [0]
    t_off = 0
    for b in blocks:
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
        t_off += t.shape[0]
    nt = t_off
    return K.Zones(tets=np.concatenate(tets), dn=np.concatenate(dn), vol=np.concatenate(vol),
                   wt=np.concatenate(wt), gptr=np.asarray(gptr, np.int64), gnodes=np.concatenate(gnodes),
                   gnptr=np.asarray(gnptr, np.int64), par=np.concatenate(zp), state=np.zeros((nt, K.N_ZS)),
                   stress=np.zeros((nt, 6)))


def _cells(blocks):
    """The linear cells of ``blocks``: one stiffness matrix per (element,
    cell size, Poisson's ratio), scaled by each block's E (kernels.Cells)."""
    kinds, mats, nodes, kind, scale = {}, [], [], [], []
    for b in blocks:
        size = tuple(np.round((b.hi - b.lo) / b.cells, 12))
        key = (b.element, size, b.material.nu)
        if key not in kinds:
            kinds[key] = len(mats)
            mats.append(cell_stiffness(b.element, size, b.material.nu))
        nodes.append(b.mesh.cells + b.node0)
        kind.append(np.full(b.mesh.cells.shape[0], kinds[key]))
        scale.append(np.full(b.mesh.cells.shape[0], b.material.E))
    if not blocks:
        return K.empty_cells()
    return K.Cells(nodes=np.concatenate(nodes), kind=np.concatenate(kind), scale=np.concatenate(scale),
                   K=np.array(mats))


def cell_masses(blocks, cells):
    """An eighth of each cell's mass (density x volume) per corner."""
    return np.concatenate([np.full(b.mesh.cells.shape[0], b.material.density * np.prod((b.hi - b.lo) / b.cells) / 8.0)
                           for b in blocks if b.element != "zones"])


def _with_levers(sc, points, x0):
    """Rigid blocks: a sub-contact's two bodies (its side nodes) and its
    levers from their reference points (body frame = global at the start)."""
    body = sc.nodes[:, [0, 4]].copy()
    return sc._replace(body=body, lever=points[:, None, :] - x0[body])


def _rigid(model, x0, maps, jlaw, joints, bearings, joint_points, bearing_points, contacts, fixed, vpres, monitors):
    """Per body (the blocks, then the strips) its mass and principal
    inertia (a box: m (b^2 + c^2) / 12 about each axis), lever scale (half
    its diagonal) and the Gershgorin bounds of its translational and
    rotational contact stiffness; point loads with their levers."""
    nb, nn = model.n_nodes, x0.shape[0]
    mphys = np.zeros(nn)
    inertia = np.ones((nn, 3))
    rlen = np.ones(nn)
    for b in model.blocks:
        size = b.hi - b.lo
        m = b.material.density * float(np.prod(size))
        mphys[b.node0] = m
        inertia[b.node0] = m / 12.0 * (np.sum(size ** 2) - size ** 2)
        rlen[b.node0] = 0.5 * float(np.linalg.norm(size))
    rfixed = np.zeros((nn, 3), np.uint8)
    rfixed[nb:] = 1
    for s in model.strips:
        if s.turn >= 0:
            rfixed[nb + s.index, s.turn] = 0
    ompres = np.zeros((nn, 3))
    for bid, dd in model.rotation_fixities.items():
        for dof, w in dd.items():
            rfixed[model.blocks[bid].node0, dof] = 1
            ompres[model.blocks[bid].node0, dof] = w
    joints = _with_levers(joints, joint_points, x0)
    bearings = _with_levers(bearings, bearing_points, x0)
    kt, kr = np.zeros(nn), np.zeros(nn)
    rigid_contact_stiffness(kt, kr, joints)
    rigid_contact_stiffness(kt, kr, bearings)
    loads = (model.point_loads + [(nd, x0[nd], f) for nd, f in model.forces.items()]
             + [(nb + s.index, s.x0, s.force) for s in model.strips if s.force is not None])
    bodies = K.Bodies(
        R=np.repeat(np.eye(3)[None], nn, axis=0), om=np.zeros((nn, 3)), mom=np.zeros((nn, 3)),
        iinv=np.zeros((nn, 3, 3)), rfixed=rfixed, ompres=ompres, rlen=rlen, fl=np.zeros((nn, 3)),
        load_body=np.array([nd for nd, _, _ in loads], np.int64),
        load_lever=np.array([p - x0[nd] for nd, p, _ in loads], float).reshape(-1, 3),
        load_force=np.array([f for _, _, f in loads], float).reshape(-1, 3))
    return Assembly(
        rigid=True, large=bool(model.large), zlaw=K.ZONE_NONE, jlaw=jlaw,
        nodes=_nodes(x0, mphys, fixed, vpres, np.zeros((nn, 3))), zones=K.empty_zones(), cells=K.empty_cells(),
        joints=joints, bearings=bearings, bodies=bodies, monitors=monitors, joint_points=joint_points,
        bearing_points=bearing_points, contacts=contacts,
        stiffness=np.repeat(kt[:, None], 3, axis=1), rot_stiffness=kr, inertia=inertia,
        h_min=float(np.min(rlen)),
        block_of_node=np.concatenate([np.arange(nb), np.full(nn - nb, -1)]), **maps)
