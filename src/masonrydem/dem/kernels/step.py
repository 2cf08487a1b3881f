"""The explicit time step: central differences with Cundall's local
non-viscous damping (Itasca FLAC3D/3DEC), for deformable and rigid blocks.

    F = F_int + lf F_ext + m_g g
    v(t+dt/2) = v(t-dt/2) + dt/m (F - alpha |F| sgn(v(t-dt/2))),
    u(t+dt)   = u(t) + dt v(t+dt/2)                   (per component)

``run_chunk_entry`` specialises ``run_chunk`` on literal law ids and
flags (zone law, joint law, rigid blocks, large displacements, gravity),
so a model compiles and runs only the laws and effects it declares, and
the on-disk cache keeps one entry per combination actually used.
"""
import math

from numba import literally, njit
from numba.extending import overload

from .cells import cell_forces
from .joints import contact_forces
from .layout import H_KE, H_MON, H_RATIO, H_STEP, JOINT_BEARING, ST_NONFINITE, ST_OK, Bodies, Contacts, Nodes, Zones
from .linalg import add_force, body_vec, rotate_by
from .static import choose
from .zones import zone_forces

_CACHE = dict(cache=True, nogil=True, error_model="numpy")
_INLINE = dict(cache=True, inline="always", error_model="numpy")


@njit(**_INLINE)
def _advance_dof(ff, fa, vo, m, fixed, vp, vf, alpha, dt):
    """One translational component of a node (or body): its total force ff
    (fa the applied part), velocity vo, mass m; either its prescribed
    velocity vf vp (the force is a reaction) or central differences with
    local damping.  Returns (its new velocity, its contributions to sum |F|
    free, sum |applied|, kinetic energy, work rate).  (A function of
    scalars: one that took the arrays and branched kept numba's reference
    counting in the loop.)"""
    if fixed:
        vv = vf * vp
        return vv, 0.0, abs(ff), 0.0, -ff * vv
    # local damping against the velocity, without a branch on its sign
    # (which is near random in a quasi-static run): sgn(0) = 0
    fd = ff - alpha * abs(ff) * ((vo > 0.0) - (vo < 0.0))
    vv = vo + dt * fd / m
    return vv, abs(ff), abs(fa), 0.5 * m * vv * vv, fa * vv


@njit(**_INLINE)
def _advance_nodes(gon, grav, vf, alpha, ctl, nodes, sums):
    """Deformable blocks: every node's components of every lane as
    ``_advance_dof``, in two passes over the flat (3 n, S) arrays: first the
    elementwise update of forces, velocities and displacements, without a
    branch on a lane's values (a prescribed component's velocity is
    selected, and whether a component is prescribed is one for all
    lanes), which vectorises across the lanes; then per lane the four sums
    in the order of the components.  ``sums`` (4, S): per lane sum |F|
    free, sum |applied|, kinetic energy, work rate."""
    nl = nodes.u.shape[2]
    n = nodes.u.shape[0] * 3
    u, v, f = nodes.u.reshape(n, nl), nodes.v.reshape(n, nl), nodes.f.reshape(n, nl)
    mass, vpres, fext = nodes.mass.reshape(n, nl), nodes.vpres.reshape(n, nl), nodes.fext.reshape(n, nl)
    fixed = nodes.fixed.reshape(n)
    dt, lf = ctl.dt, ctl.lf
    for k in range(n):
        fk = fixed[k]
        for b in range(nl):
            load = lf[b] * fext[k, b]
            if gon:
                load += nodes.mgrav[k // 3, b] * grav[k % 3]
            ff = f[k, b] + load
            f[k, b] = ff
            vo = v[k, b]
            fd = ff - alpha[b] * abs(ff) * ((vo > 0.0) - (vo < 0.0))
            vv = vf[b] * vpres[k, b] if fk else vo + dt[b] * fd / mass[k, b]
            v[k, b] = vv
            u[k, b] += dt[b] * vv
    sums[:, :] = 0.0
    for k in range(n):
        fk = fixed[k]
        for b in range(nl):
            ff, vv = f[k, b], v[k, b]
            load = lf[b] * fext[k, b]
            if gon:
                load += nodes.mgrav[k // 3, b] * grav[k % 3]
            if fk:
                sums[1, b] += abs(ff)
                sums[3, b] += -ff * vv
            else:
                sums[0, b] += abs(ff)
                sums[1, b] += abs(load)
                sums[2, b] += 0.5 * mass[k, b] * vv * vv
                sums[3, b] += load * vv


@njit(**_INLINE)
def _advance_bodies(gon, grav, vf, alpha, dt, nodes, bodies):
    """Rigid blocks (one node per body): each body's translation, its
    point loads summed into bodies.fl, by ``_advance_dof`` per component,
    then its rotation (``_advance_rotation``).  Returns the sums as
    ``_advance_nodes``."""
    u, v, f, mass, fixed, vpres = nodes.u, nodes.v, nodes.f, nodes.mass, nodes.fixed, nodes.vpres
    unbal = 0.0
    applied = 0.0
    ke = 0.0
    wk = 0.0
    for i in range(u.shape[0]):
        for d in range(3):
            load = bodies.fl[i, d]
            if gon:     # gravity only when the scene declares it (literal: compiled away otherwise)
                load += nodes.mgrav[i] * grav[d]
            ff = f[i, d] + load
            f[i, d] = ff
            vv, a0, a1, a2, a3 = _advance_dof(ff, load, v[i, d], mass[i, d], fixed[i, d], vpres[i, d], vf, alpha, dt)
            v[i, d] = vv
            u[i, d] += dt * vv
            unbal += a0
            applied += a1
            ke += a2
            wk += a3
        unbal, applied, ke, wk = _advance_rotation(i, vf, alpha, dt, bodies, unbal, applied, ke, wk)
    return unbal, applied, ke, wk


@njit(**_INLINE)
def _point_loads(lf, bodies):
    """Rigid blocks: the point loads (times lf) summed per body into
    bodies.fl, their moments into bodies.mom."""
    R, fl, mom = bodies.R, bodies.fl, bodies.mom
    lever, force = bodies.load_lever, bodies.load_force
    for k in range(bodies.load_body.shape[0]):
        bd = bodies.load_body[k]
        rx, ry, rz = body_vec(R, bd, lever[k, 0], lever[k, 1], lever[k, 2])
        add_force(fl, mom, bd, rx, ry, rz, lf * force[k, 0], lf * force[k, 1], lf * force[k, 2])


@njit(**_INLINE)
def _advance_rotation(i, vf, alpha, dt, bodies, unbal, applied, ke, wk):
    """The rotation of rigid body i, as ``_advance_dof`` per component:
    free components with local damping, om += dt R iinv R^T M (inverse
    inertia in the body frame; no gyroscopic term om x I om: exact for
    rotation about a principal axis, irrelevant to quasi-static runs);
    prescribed ones take vf ompres and their moment is a reaction.
    Moments count in the force ratio divided by the body's lever scale.
    Returns the sums (unbalanced, applied, kinetic energy, work rate)
    with this body's contributions added."""
    R, om, mom, iinv = bodies.R, bodies.om, bodies.mom, bodies.iinv
    rfixed, ompres, rlen = bodies.rfixed, bodies.ompres, bodies.rlen
    mx = 0.0
    my = 0.0
    mz = 0.0
    for d in range(3):
        md = mom[i, d]
        if rfixed[i, d]:
            applied += abs(md) / rlen[i]
            wk -= md * vf * ompres[i, d]
            continue
        unbal += abs(md) / rlen[i]
        if om[i, d] > 0.0:
            md -= alpha * abs(md)
        elif om[i, d] < 0.0:
            md += alpha * abs(md)
        if d == 0:
            mx = md
        elif d == 1:
            my = md
        else:
            mz = md
    # om += dt R iinv R^T M (to the body frame, times iinv, back)
    bx = R[i, 0, 0] * mx + R[i, 1, 0] * my + R[i, 2, 0] * mz
    by = R[i, 0, 1] * mx + R[i, 1, 1] * my + R[i, 2, 1] * mz
    bz = R[i, 0, 2] * mx + R[i, 1, 2] * my + R[i, 2, 2] * mz
    ax_ = iinv[i, 0, 0] * bx + iinv[i, 0, 1] * by + iinv[i, 0, 2] * bz
    ay_ = iinv[i, 1, 0] * bx + iinv[i, 1, 1] * by + iinv[i, 1, 2] * bz
    az_ = iinv[i, 2, 0] * bx + iinv[i, 2, 1] * by + iinv[i, 2, 2] * bz
    gx, gy, gz = body_vec(R, i, ax_, ay_, az_)
    om[i, 0] = vf * ompres[i, 0] if rfixed[i, 0] else om[i, 0] + dt * gx
    om[i, 1] = vf * ompres[i, 1] if rfixed[i, 1] else om[i, 1] + dt * gy
    om[i, 2] = vf * ompres[i, 2] if rfixed[i, 2] else om[i, 2] + dt * gz
    # kinetic energy of rotation: 1/2 (R^T om) . I (R^T om), I diagonal in the body frame
    wx = R[i, 0, 0] * om[i, 0] + R[i, 1, 0] * om[i, 1] + R[i, 2, 0] * om[i, 2]
    wy = R[i, 0, 1] * om[i, 0] + R[i, 1, 1] * om[i, 1] + R[i, 2, 1] * om[i, 2]
    wz = R[i, 0, 2] * om[i, 0] + R[i, 1, 2] * om[i, 1] + R[i, 2, 2] * om[i, 2]
    ke += 0.5 * (wx * wx / iinv[i, 0, 0] + wy * wy / iinv[i, 1, 1] + wz * wz / iinv[i, 2, 2])
    rotate_by(R[i], dt * om[i, 0], dt * om[i, 1], dt * om[i, 2])
    return unbal, applied, ke, wk


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
def _record_step(step, b, ctl, hist, sums, nodes, mon):
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
def _rigid_lanes(zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                 scratch):
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
        _point_loads(ctl.lf[b], lb)
        sums[0, b], sums[1, b], sums[2, b], sums[3, b] = _advance_bodies(gon, grav, vf[b], alpha[b], ctl.dt[b], ln,
                                                                         lb)


@njit(**_INLINE)
def _deformable_lanes(zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                      scratch):
    """Deformable blocks: the zones lane by lane on the lane's views, then
    across the lanes the cells, the sub-contacts and the nodes' advance;
    each lane's sums into scratch.sums."""
    nl = nodes.u.shape[2]
    for b in range(nl):
        zone_forces(zlaw, ctl.dt[b], lane_nodes(nodes, b), lane_zones(zones, b), scratch)
    cell_forces(nodes, cells, scratch)
    contact_forces(jlaw, 0, large, ctl.dt, nodes, bodies, joints)
    contact_forces(JOINT_BEARING, 0, large, ctl.dt, nodes, bodies, bearings)
    _advance_nodes(gon, grav, vf, alpha, ctl, nodes, scratch.sums)


def lanes_forward(rigid, zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                  scratch):
    """One step's forces and advance of every lane, for rigid or deformable
    blocks (``rigid`` a literal: static.py)."""
    raise TypeError("lanes_forward: only callable from compiled code")


@overload(lanes_forward, prefer_literal=True)
def _lanes_forward(rigid, zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                   scratch):
    impl = choose({0: _deformable_lanes, 1: _rigid_lanes}, rigid, "rigid")
    return (lambda rigid, zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
            scratch: impl(zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings, bodies,
                          scratch))


@njit(**_CACHE)
def run_chunk(zlaw, jlaw, rigid, large, gon, nsteps, ctl, nodes, zones, cells, joints, bearings, bodies, mon, hist,
              work, scratch):
    """Advances every lane ``nsteps`` steps (module docstring).

    Constrained components take their prescribed velocity times the
    velocity factor min(1, vf0 + (step + 1) dvf), step counted from the
    start of the lane's chunk (a linear ramp that starts loading without
    an inertial shock); the force they carry is their reaction.  The
    unbalanced-force ratio is sum |F| over free components / sum of
    |applied| forces (external, gravity, and reactions of the constrained
    components).  ``work[0, b]`` accumulates the work done on lane b's
    model (``work[1, b]``: its largest value so far): reactions times the
    prescribed velocities and applied forces times the free velocities.
    The zone law and rigid blocks run lane by lane on the lane's views;
    the cells, the deformable sub-contacts and the nodes across the lanes.
    Returns (status, steps done); status ST_NONFINITE stops every lane
    after the first step at which a lane's kinetic energy or force ratio
    is not finite (the caller tells which from the history)."""
    nl = nodes.u.shape[2]
    f = nodes.f
    alpha, grav = ctl.alpha, ctl.gravity
    sums, vf = scratch.sums, scratch.vf
    for step in range(nsteps):
        for b in range(nl):
            vf[b] = min(1.0, ctl.vf0[b] + (ctl.k0[b] + step + 1) * ctl.dvf[b])
        f[:, :, :] = 0.0
        lanes_forward(rigid, zlaw, jlaw, large, gon, grav, vf, alpha, ctl, nodes, zones, cells, joints, bearings,
                      bodies, scratch)
        finite = True
        for b in range(nl):
            work[0, b] += ctl.dt[b] * sums[3, b]
            if work[0, b] > work[1, b]:
                work[1, b] = work[0, b]
            finite &= _record_step(step, b, ctl, hist, sums, nodes, mon)
        if not finite:
            return ST_NONFINITE, step + 1
    return ST_OK, nsteps


@njit(**_CACHE)
def run_chunk_entry(zlaw, jlaw, rigid, large, gon, nsteps, ctl, nodes, zones, cells, joints, bearings, bodies, mon,
                    hist, work, scratch):
    """Entry point: ``run_chunk`` specialised on the literal law ids and
    flags, so only the laws and effects a model uses are compiled (and
    cached)."""
    return run_chunk(literally(zlaw), literally(jlaw), literally(rigid), literally(large), literally(gon), nsteps,
                     ctl, nodes, zones, cells, joints, bearings, bodies, mon, hist, work, scratch)


def specialised(args):
    """The compiled specialisation of ``run_chunk_entry`` for the literal law
    ids and flags (and the argument types) of ``args``, its arguments, as a
    function that calls it directly.  Called through ``run_chunk_entry``,
    numba resolves the literals anew at every call (about 5 ms: 0.2 s of a
    study run's 40 chunks); the specialisation found once runs at once.
    Falls back to ``run_chunk_entry`` if none matches."""
    from numba import typeof
    run_chunk_entry(*args[:5], 0, *args[6:])          # compiled (or loaded from the cache) for these literals
    literals = tuple(int(x) for x in args[:5])
    types = tuple(typeof(x) for x in args[5:])
    for sig, cres in run_chunk_entry.overloads.items():
        if tuple(getattr(t, "literal_value", None) for t in sig[:5]) == literals and tuple(sig[5:]) == types:
            return cres.entry_point
    return run_chunk_entry
