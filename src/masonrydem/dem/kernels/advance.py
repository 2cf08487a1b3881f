"""The update of the nodes and rigid bodies in a step (step.py): central
differences with Cundall's local non-viscous damping, per component, and
the sums the stop rules read (unbalanced force, applied load, kinetic
energy, work rate)."""
from numba import njit

from .linalg import add_force, body_vec, rotate_by

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
def advance_nodes(gon, lf, grav, vf, alpha, dt, nodes):
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
def advance_bodies(gon, grav, vf, alpha, dt, nodes, bodies):
    """Rigid blocks (one node per body): each body's translation, its
    point loads summed into bodies.fl, by ``_advance_dof`` per component,
    then its rotation (``_advance_rotation``).  Returns the sums as
    ``advance_nodes``."""
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
def point_loads(lf, bodies):
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
