"""The explicit time step: central differences with Cundall's local
non-viscous damping (Itasca FLAC3D/3DEC), for deformable and rigid blocks.

    F = F_int + lf F_ext + m_g g
    v(t+dt/2) = v(t-dt/2) + dt/m (F - alpha |F| sgn(v(t-dt/2))),
    u(t+dt)   = u(t) + dt v(t+dt/2)                   (per component)

``specialised`` gives the kernel that advances every lane of a batch
(kernels/layout.py): a batch of one runs the kernels of one simulation
(``_one_lane``: cells.py, joints.py, zones.py and advance.py), a wider
one those of lanes.py, eight lanes at a time, with the zones and rigid
blocks lane by lane on each lane's views.  Each is compiled for literal
law ids, flags and lanes (zone law, joint law, rigid blocks, large
displacements, gravity, the batch's width), so a model compiles and runs
only the laws and effects it declares, and the on-disk cache keeps one
entry per combination actually used.
"""
import math

from numba import njit, typeof, types
from numba.extending import overload

from . import lanes as L
from .advance import advance_bodies, advance_nodes, point_loads
from .cells import cell_forces
from .joints import contact_forces
from .layout import (CONTACTS_FORTRAN, H_KE, H_MON, H_RATIO, H_STEP, JOINT_BEARING, ST_NONFINITE, ST_OK, Bodies, Cells,
                     Contacts, Nodes, Zones)
from .static import choose
from .zones import zone_forces

_CACHE = dict(cache=True, nogil=True, error_model="numpy")
_INLINE = dict(cache=True, inline="always", error_model="numpy")


@njit(**_INLINE)
def _record_step(step, step0, hist, unbal, applied, ke, nodes, mon):
    """Row ``step`` of the history (layout.H_*): step number, unbalanced-
    force ratio, kinetic energy, per monitor group the reaction (sum of -F
    along its component) and the summed displacement.  Returns False if
    the step is not finite."""
    ngrp = (hist.shape[1] - H_MON) // 2
    hist[step, H_STEP] = step0 + step + 1
    if applied > 0.0:
        hist[step, H_RATIO] = unbal / applied
    else:
        hist[step, H_RATIO] = 0.0 if unbal == 0.0 else math.inf
    hist[step, H_KE] = ke
    for gi in range(ngrp):
        hist[step, H_MON + 2 * gi] = 0.0
        hist[step, H_MON + 1 + 2 * gi] = 0.0
    f, u = nodes.f, nodes.u
    for k in range(mon.nodes.shape[0]):
        gi = mon.group[k]
        nd = mon.nodes[k]
        d = mon.dof[k]
        hist[step, H_MON + 2 * gi] -= f[nd, d]
        hist[step, H_MON + 1 + 2 * gi] += u[nd, d]
    return math.isfinite(ke) and math.isfinite(hist[step, H_RATIO])


@njit(**_INLINE)
def lane_nodes(nodes, b):
    """Lane b's view of the nodes (a run's arrays, as the lane-free
    kernels take them)."""
    return Nodes(nodes.x0, nodes.u[:, :, b], nodes.v[:, :, b], nodes.f[:, :, b], nodes.mass[:, :, b],
                 nodes.mgrav[:, b], nodes.fixed, nodes.vpres[:, :, b], nodes.fext[:, :, b])


@njit(**_INLINE)
def lane_zones(zones, b):
    return Zones(zones.tets, zones.dn, zones.vol, zones.wt, zones.gptr, zones.gnodes, zones.gnptr,
                 zones.par[:, :, b], zones.state[:, :, b], zones.stress[:, :, b])


@njit(**_INLINE)
def lane_contacts(sc, b, nl):
    return Contacts(sc.nodes, sc.cnt, sc.w, sc.body, sc.lever, sc.axes, sc.area, sc.par[b::nl], sc.state[b::nl],
                    sc.force[b::nl], sc.gptr, sc.gs, sc.gw)


@njit(**_INLINE)
def lane_bodies(bodies, b):
    return Bodies(bodies.R[:, :, :, b], bodies.om[:, :, b], bodies.mom[:, :, b], bodies.iinv[:, :, :, b],
                  bodies.rfixed, bodies.ompres[:, :, b], bodies.rlen, bodies.fl[:, :, b], bodies.load_body,
                  bodies.load_lever, bodies.load_force[:, :, b])


@njit(**_INLINE)
def _record_lane(step, b, ctl, hist, sums, nodes, mon):
    """Row ``step`` of lane b's history (layout.H_*): step number,
    unbalanced-force ratio, kinetic energy, per monitor group the reaction
    (sum of -F along its component) and the summed displacement.  Returns
    False if the step is not finite."""
    ngrp = (hist.shape[1] - H_MON) // 2
    unbal, applied, ke = sums[0, b], sums[1, b], sums[2, b]
    hist[step, H_STEP, b] = ctl.step0[b] + ctl.k0[b] + step + 1
    if applied > 0.0:
        hist[step, H_RATIO, b] = unbal / applied
    else:
        hist[step, H_RATIO, b] = 0.0 if unbal == 0.0 else math.inf
    hist[step, H_KE, b] = ke
    for gi in range(ngrp):
        hist[step, H_MON + 2 * gi, b] = 0.0
        hist[step, H_MON + 1 + 2 * gi, b] = 0.0
    f, u = nodes.f, nodes.u
    for k in range(mon.nodes.shape[0]):
        gi = mon.group[k]
        nd = mon.nodes[k]
        d = mon.dof[k]
        hist[step, H_MON + 2 * gi, b] -= f[nd, d, b]
        hist[step, H_MON + 1 + 2 * gi, b] += u[nd, d, b]
    return math.isfinite(ke) and math.isfinite(hist[step, H_RATIO, b])


@njit(**_INLINE)
def _one(nodes, zones, cells, joints, bearings, bodies):
    """The containers of a batch of one as one simulation's arrays (the
    lane axis, of length one, dropped: C-contiguous views)."""
    n, nt, nb, nk = nodes.u.shape[0], zones.par.shape[0], bodies.R.shape[0], bodies.load_force.shape[0]
    return (Nodes(nodes.x0, nodes.u.reshape(n, 3), nodes.v.reshape(n, 3), nodes.f.reshape(n, 3),
                  nodes.mass.reshape(n, 3), nodes.mgrav.reshape(n), nodes.fixed, nodes.vpres.reshape(n, 3),
                  nodes.fext.reshape(n, 3)),
            Zones(zones.tets, zones.dn, zones.vol, zones.wt, zones.gptr, zones.gnodes, zones.gnptr,
                  zones.par.reshape(nt, zones.par.shape[1]), zones.state.reshape(nt, zones.state.shape[1]),
                  zones.stress.reshape(nt, 6)),
            Cells(cells.nodes, cells.kind, cells.scale.reshape(cells.scale.shape[0]), cells.K),
            joints, bearings,
            Bodies(bodies.R.reshape(nb, 3, 3), bodies.om.reshape(nb, 3), bodies.mom.reshape(nb, 3),
                   bodies.iinv.reshape(nb, 3, 3), bodies.rfixed, bodies.ompres.reshape(nb, 3), bodies.rlen,
                   bodies.fl.reshape(nb, 3), bodies.load_body, bodies.load_lever, bodies.load_force.reshape(nk, 3)))


@njit(**_CACHE)
def _one_lane(zlaw, jlaw, rigid, large, gon, nl, nsteps, ctl, nodes, zones, cells, joints, bearings, bodies, mon,
              hist, work, scratch):
    """A batch of one (``nl`` 1): the steps of one simulation
    (``specialised``)."""
    nodes, zones, cells, joints, bearings, bodies = _one(nodes, zones, cells, joints, bearings, bodies)
    hist = hist.reshape(hist.shape[0], hist.shape[1])
    work = work.reshape(2)
    f = nodes.f
    dt, alpha, lf, grav, vf0, dvf, step0 = ctl.dt[0], ctl.alpha[0], ctl.lf[0], ctl.gravity, ctl.vf0[0], ctl.dvf[0], \
        ctl.step0[0] + ctl.k0[0]
    for step in range(nsteps):
        vf = min(1.0, vf0 + (ctl.k0[0] + step + 1) * dvf)
        f[:, :] = 0.0
        if rigid:
            bodies.fl[:, :] = 0.0
            bodies.mom[:, :] = 0.0
        zone_forces(zlaw, dt, nodes, zones, scratch)
        cell_forces(nodes, cells, scratch)
        contact_forces(jlaw, rigid, large, dt, nodes, bodies, joints)
        contact_forces(JOINT_BEARING, rigid, large, dt, nodes, bodies, bearings)
        if rigid:
            point_loads(lf, bodies)
            unbal, applied, ke, wk = advance_bodies(gon, grav, vf, alpha, dt, nodes, bodies)
        else:
            unbal, applied, ke, wk = advance_nodes(gon, lf, grav, vf, alpha, dt, nodes)
        work[0] += dt * wk
        if work[0] > work[1]:
            work[1] = work[0]
        if not _record_step(step, step0, hist, unbal, applied, ke, nodes, mon):
            return ST_NONFINITE, step + 1
    return ST_OK, nsteps


@njit(**_INLINE)
def _rigid_lanes(zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                 scratch, nl):
    """Rigid blocks, lane by lane on the lane's views: the contact forces
    and moments, the point loads, the bodies' advance; each lane's sums
    into scratch.sums."""
    nl = nodes.u.shape[2]
    sums = scratch.sums
    bodies.fl[:, :, :] = 0.0
    bodies.mom[:, :, :] = 0.0
    for b in range(nl):
        ln, lb = lane_nodes(nodes, b), lane_bodies(bodies, b)
        contact_forces(jlaw, 1, large, ctl.dt[b], ln, lb, lane_contacts(joints, b, nl))
        contact_forces(JOINT_BEARING, 1, large, ctl.dt[b], ln, lb, lane_contacts(bearings, b, nl))
        point_loads(ctl.lf[b], lb)
        sums[0, b], sums[1, b], sums[2, b], sums[3, b] = advance_bodies(gon, grav, vf[b], alpha[b], ctl.dt[b], ln,
                                                                         lb)


@njit(**_INLINE)
def _deformable_lanes(zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                      scratch, nl):
    """Deformable blocks: the zones lane by lane on the lane's views, then
    across the lanes the cells, the sub-contacts and the nodes' advance
    (lanes.py); each lane's sums into scratch.sums."""
    for b in range(nl):
        zone_forces(zlaw, ctl.dt[b], lane_nodes(nodes, b), lane_zones(zones, b), scratch)
    L.cell_forces(nodes, cells, nl)
    L.contact_forces(jlaw, ctl.dt, nodes, joints, nl)
    L.contact_forces(JOINT_BEARING, ctl.dt, nodes, bearings, nl)
    L.advance_nodes(gon, grav, vf, ctl, nodes, scratch.sums, nl)


def lanes_forward(rigid, zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                  scratch, nl):
    """One step's forces and advance of every lane, for rigid or deformable
    blocks (``rigid`` a literal: static.py)."""
    raise TypeError("lanes_forward: only callable from compiled code")


@overload(lanes_forward, prefer_literal=True)
def _lanes_forward(rigid, zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                   scratch, nl):
    impl = choose({0: _deformable_lanes, 1: _rigid_lanes}, rigid, "rigid")
    return (lambda rigid, zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
            scratch, nl: impl(zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings,
                              bodies, scratch, nl))


@njit(**_CACHE)
def _lanes(zlaw, jlaw, rigid, large, gon, nl, nsteps, ctl, nodes, zones, cells, joints, bearings, bodies, mon, hist,
           work, scratch):
    """A batch of 8, 16, ... lanes (``specialised``)."""
    f = nodes.f
    alpha, grav = ctl.alpha, ctl.gravity
    sums, vf = scratch.sums, scratch.vf
    for step in range(nsteps):
        for b in range(nl):
            vf[b] = min(1.0, ctl.vf0[b] + (ctl.k0[b] + step + 1) * ctl.dvf[b])
        f[:, :, :] = 0.0
        lanes_forward(rigid, zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings,
                      bodies, scratch, nl)
        finite = True
        for b in range(nl):
            work[0, b] += ctl.dt[b] * sums[3, b]
            if work[0, b] > work[1, b]:
                work[1, b] = work[0, b]
            finite &= _record_lane(step, b, ctl, hist, sums, nodes, mon)
        if not finite:
            return ST_NONFINITE, step + 1
    return ST_OK, nsteps


LITERALS = 6        # the leading arguments that are literals


def _argument_type(x):
    """numba's type of a kernel argument, but that a sub-contact set's
    Fortran-ordered arrays (layout.CONTACTS_FORTRAN) are Fortran arrays
    also where they are C-contiguous as well (no row or one, which
    numba's typeof calls C), so that a model with an empty set compiles to
    the same specialisation as one with sub-contacts."""
    if isinstance(x, Contacts):
        return types.BaseTuple.from_types(
            [typeof(a).copy(layout="F") if f in CONTACTS_FORTRAN and a.flags.f_contiguous else typeof(a)
             for f, a in zip(x._fields, x)], Contacts)
    return typeof(x)


def specialised(args):
    """The step kernel for ``args``, its arguments (zlaw, jlaw, rigid,
    large, gon, nl, nsteps, ctl, nodes, zones, cells, joints, bearings,
    bodies, mon, hist, work, scratch), compiled for their literal law ids,
    flags and lanes (the first ``LITERALS``) and their types, or loaded
    from the on-disk cache: a function that takes the same arguments and
    advances every lane ``nsteps`` steps, a batch of one by ``_one_lane``,
    a wider one by ``_lanes``.  Resolved once, it runs at once.

    Constrained components take their prescribed velocity times the
    velocity factor min(1, vf0 + (step + 1) dvf), step counted from the
    start of the lane's chunk (a linear ramp that starts loading without
    an inertial shock); the force they carry is their reaction.  The
    unbalanced-force ratio is sum |F| over free components / sum of
    |applied| forces (external, gravity, and reactions of the constrained
    components).  ``work[0, b]`` accumulates the work done on lane b's
    model (``work[1, b]``: its largest value so far): reactions times the
    prescribed velocities and applied forces times the free velocities.
    The function returns (status, steps done); status ST_NONFINITE stops
    every lane after the first step at which a lane's kinetic energy or
    force ratio is not finite (the caller tells which from the history).
    ``nl``: the lanes, 1 or a multiple of 8."""
    sig = tuple(types.literal(int(x)) for x in args[:LITERALS]) + tuple(_argument_type(x) for x in args[LITERALS:])
    kernel = _one_lane if sig[5].literal_value == 1 else _lanes
    kernel.compile(sig)
    return kernel.overloads[sig].entry_point
