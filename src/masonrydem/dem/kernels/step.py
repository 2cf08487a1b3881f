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

from .cells import cell_forces
from .joints import contact_forces
from .layout import H_KE, H_MON, H_RATIO, H_STEP, JOINT_BEARING, ST_NONFINITE, ST_OK
from .linalg import add_force, body_vec, rotate_by
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
def _advance_nodes(gon, lf, grav, vf, alpha, dt, nodes):
    """Deformable blocks: every node's components as ``_advance_dof``, in
    two passes over the flat (n x 3) arrays: first the elementwise update
    of forces, velocities and displacements, without a branch (a
    prescribed component's velocity is selected, not branched to), which
    vectorises; then the four sums in the order of the components, the
    same sums as before to the last bit.  Returns (sum |F| free, sum
    |applied|, kinetic energy, work rate)."""
    n = nodes.u.shape[0] * 3
    u, v, f = nodes.u.reshape(n), nodes.v.reshape(n), nodes.f.reshape(n)
    mass, fixed, vpres, fext = nodes.mass.reshape(n), nodes.fixed.reshape(n), nodes.vpres.reshape(n), \
        nodes.fext.reshape(n)
    for k in range(n):
        load = lf * fext[k]
        if gon:
            load += nodes.mgrav[k // 3] * grav[k % 3]
        ff = f[k] + load
        f[k] = ff
        vo = v[k]
        fd = ff - alpha * abs(ff) * ((vo > 0.0) - (vo < 0.0))
        vv = vf * vpres[k] if fixed[k] else vo + dt * fd / mass[k]
        v[k] = vv
        u[k] += dt * vv
    unbal = 0.0
    applied = 0.0
    ke = 0.0
    wk = 0.0
    for k in range(n):
        ff, vv = f[k], v[k]
        load = lf * fext[k]
        if gon:
            load += nodes.mgrav[k // 3] * grav[k % 3]
        if fixed[k]:
            applied += abs(ff)
            wk += -ff * vv
        else:
            unbal += abs(ff)
            applied += abs(load)
            ke += 0.5 * mass[k] * vv * vv
            wk += load * vv
    return unbal, applied, ke, wk


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


@njit(**_CACHE)
def run_chunk(zlaw, jlaw, rigid, large, gon, nsteps, ctl, nodes, zones, cells, joints, bearings, bodies, mon, hist,
              work, scratch):
    """Advances ``nsteps`` steps (module docstring).

    Constrained components take their prescribed velocity times the
    velocity factor min(1, vf0 + (step + 1) dvf) (a linear ramp that starts
    loading without an inertial shock); the force they carry is their
    reaction.  The unbalanced-force ratio is sum |F| over free components
    / sum of |applied| forces (external, gravity, and reactions of the
    constrained components).  ``work[0]`` accumulates the work done on the
    model (``work[1]``: its largest value so far): reactions times the
    prescribed velocities and applied forces times the free velocities.
    Returns (status, steps done); status ST_NONFINITE stops at the first
    step whose kinetic energy is not finite."""
    f = nodes.f
    dt, alpha, lf, grav = ctl.dt, ctl.alpha, ctl.lf, ctl.gravity
    for step in range(nsteps):
        vf = min(1.0, ctl.vf0 + (step + 1) * ctl.dvf)
        f[:, :] = 0.0
        if rigid:
            bodies.fl[:, :] = 0.0
            bodies.mom[:, :] = 0.0
        zone_forces(zlaw, dt, nodes, zones, scratch)
        cell_forces(nodes, cells, scratch)
        contact_forces(jlaw, rigid, large, dt, nodes, bodies, joints)
        contact_forces(JOINT_BEARING, rigid, large, dt, nodes, bodies, bearings)
        if rigid:
            _point_loads(lf, bodies)
            unbal, applied, ke, wk = _advance_bodies(gon, grav, vf, alpha, dt, nodes, bodies)
        else:
            unbal, applied, ke, wk = _advance_nodes(gon, lf, grav, vf, alpha, dt, nodes)
        work[0] += dt * wk
        if work[0] > work[1]:
            work[1] = work[0]
        if not _record_step(step, ctl.step0, hist, unbal, applied, ke, nodes, mon):
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
