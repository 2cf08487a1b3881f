"""The forces of the sub-contacts of one simulation: its relative
displacement increments gathered from its nodes (or rigid bodies), the
joint law (joint_laws.py) on every sub-contact, and the tractions spread
back as forces.  Deformable and rigid blocks differ only in how a
sub-contact's relative velocity is gathered and its force spread.  (The
same across the lanes of a batch: lanes.py.)
"""
from numba import njit
from numba.extending import overload

from .joint_laws import joint_law
from .layout import JS_D, JS_SN, JS_SP, JS_T1, JS_T2, JS_WP
from .linalg import add_force, body_vec
from .static import choose

_INLINE = dict(cache=True, inline="always", error_model="numpy")
# a law's sub-contact kernel is a function of its own, compiled (and cached)
# once for each law and block kind and shared by every step kernel that
# uses them (numba would copy an inline="always" one into each)
_CALL = dict(cache=True, error_model="numpy")


@njit(**_INLINE)
def local_increments(dt, rx, ry, rz, nx, ny, nz, ax, ay, az, bx, by, bz):
    """du = dt (v_B - v_A), v_B - v_A = (rx, ry, rz), in the local axes
    n (A to B), t1, t2: (du_n, du_s1, du_s2)."""
    return dt * (rx * nx + ry * ny + rz * nz), dt * (rx * ax + ry * ay + rz * az), dt * (rx * bx + ry * by + rz * bz)


@njit(**_INLINE)
def _params(jp, s):
    """Sub-contact s's parameters, a tuple (the columns JP_*)."""
    return jp[s, 0], jp[s, 1], jp[s, 2], jp[s, 3], jp[s, 4], jp[s, 5], jp[s, 6], jp[s, 7], jp[s, 8]


@njit(**_INLINE)
def _state(js, s):
    """Sub-contact s's state, a tuple (the columns JS_*)."""
    return js[s, 0], js[s, 1], js[s, 2], js[s, 3], js[s, 4], js[s, 5]


@njit(**_INLINE)
def _set_state(js, s, st):
    """Sub-contact s's state set to the tuple st."""
    js[s, JS_SN] = st[0]
    js[s, JS_T1] = st[1]
    js[s, JS_T2] = st[2]
    js[s, JS_WP] = st[3]
    js[s, JS_SP] = st[4]
    js[s, JS_D] = st[5]


@njit(**_INLINE)
def subcontact_law(jlaw, s, dun, dus1, dus2, jp, js):
    """The law ``jlaw`` on sub-contact s under the local displacement
    increments: reads its parameters and state, writes its new state (the
    law's branches are in a function of scalars)."""
    _set_state(js, s, joint_law(jlaw, _params(jp, s), _state(js, s), dun, dus1, dus2))


@njit(**_INLINE)
def laws(jlaw, dun, dus1, dus2, jp, js):
    """The law ``jlaw`` on every row s of ``jp`` and ``js`` (a sub-contact,
    or a sub-contact's lane) under the increments dun[s], dus1[s],
    dus2[s]: a loop that LLVM vectorises over the rows, the law being
    straight-line code (joint_laws.py).  (Written out here: a loop that
    calls ``subcontact_law`` stays scalar: 2.5 times the cost.)"""
    for s in range(js.shape[0]):
        _set_state(js, s, joint_law(jlaw, _params(jp, s), _state(js, s), dun[s], dus1[s], dus2[s]))


@njit(**_INLINE)
def traction_force(s, js, area, nx, ny, nz, ax, ay, az, bx, by, bz):
    """The force area (sigma_n n + tau_1 t1 + tau_2 t2) of sub-contact s on
    side A (its opposite acts on side B).  (Kept apart from
    ``subcontact_law``: an inlined function that runs the law and returns
    the force compiled to code 25 % slower per sub-contact.)"""
    ar = area[s]
    sn = js[s, JS_SN]
    s1 = js[s, JS_T1]
    s2 = js[s, JS_T2]
    return (ar * (sn * nx + s1 * ax + s2 * bx), ar * (sn * ny + s1 * ay + s2 * by),
            ar * (sn * nz + s1 * az + s2 * bz))


@njit(**_CALL)
def _deformable_contacts(jlaw, dt, nodes, sc):
    """Deformable blocks: the sub-contact's point moves with the nodes of
    each side, interpolated with the weights w[s]; its force is spread with
    the same weights (so the virtual work is consistent).

    Four loops over the sub-contacts: (1) each gathers its relative
    velocity from the used slots of each side (cnt: a slot left out has
    weight 0 and adds exactly nothing) and stores its displacement
    increments (in the work space ``force``); (2) the law (``laws``), with
    no indirect access: over the Fortran-ordered parameters and state LLVM
    emits vector code (joint_laws.py); (3) each stores its force; (4) each node
    gathers the forces of its sub-contacts (``contacts.with_gather``), in
    sub-contact order.  The values are those of one loop that runs the law
    and scatters each force to its nodes, bit for bit (the vector code does
    the same IEEE operations lane by lane)."""
    v = nodes.v
    w, ix, axes, cnt = sc.w, sc.nodes, sc.axes, sc.cnt
    jp, js, area, work = sc.par, sc.state, sc.area, sc.force
    n = area.shape[0]
    for s in range(n):
        rx = 0.0
        ry = 0.0
        rz = 0.0
        for k in range(cnt[s, 0]):
            nd = ix[s, k]
            wk = w[s, k]
            rx -= wk * v[nd, 0]
            ry -= wk * v[nd, 1]
            rz -= wk * v[nd, 2]
        for k in range(4, 4 + cnt[s, 1]):
            nd = ix[s, k]
            wk = w[s, k]
            rx += wk * v[nd, 0]
            ry += wk * v[nd, 1]
            rz += wk * v[nd, 2]
        work[s, 0], work[s, 1], work[s, 2] = local_increments(
            dt, rx, ry, rz, axes[s, 0], axes[s, 1], axes[s, 2], axes[s, 3], axes[s, 4], axes[s, 5],
            axes[s, 6], axes[s, 7], axes[s, 8])
    laws(jlaw, work[:, 0], work[:, 1], work[:, 2], jp, js)
    for s in range(n):
        work[s, 0], work[s, 1], work[s, 2] = traction_force(
            s, js, area, axes[s, 0], axes[s, 1], axes[s, 2], axes[s, 3], axes[s, 4], axes[s, 5],
            axes[s, 6], axes[s, 7], axes[s, 8])
    gather_forces(nodes.f, sc.gptr, sc.gs, sc.gw, work)


@njit(**_INLINE)
def gather_forces(f, gptr, gs, gw, force):
    """f[i] += sum_j gw[j] force[gs[j]] over j in gptr[i]:gptr[i + 1], in
    that order (``contacts.with_gather``)."""
    for i in range(gptr.shape[0] - 1):
        j0 = gptr[i]
        j1 = gptr[i + 1]
        if j0 == j1:
            continue
        fx = f[i, 0]
        fy = f[i, 1]
        fz = f[i, 2]
        for j in range(j0, j1):
            s = gs[j]
            wj = gw[j]
            fx += wj * force[s, 0]
            fy += wj * force[s, 1]
            fz += wj * force[s, 2]
        f[i, 0] = fx
        f[i, 1] = fy
        f[i, 2] = fz


@njit(**_CALL)
def _rigid_contacts(jlaw, large, dt, nodes, bodies, sc):
    """Rigid blocks: sub-contact s joins bodies A = body[s, 0] and
    B = body[s, 1] at the point with body-frame levers lever[s, 0] and
    lever[s, 1]; relative velocity (v_B + om_B x r_B) - (v_A + om_A x r_A),
    r = R r0.  The axes are the initial ones for small displacements
    (``large`` = 0) and turn with block A for large ones.  The force acts
    on A at r_A (force and moment r_A x F) and its opposite on B at r_B."""
    v, f = nodes.v, nodes.f
    R, om, mom = bodies.R, bodies.om, bodies.mom
    body, lever, axes = sc.body, sc.lever, sc.axes
    jp, js, area = sc.par, sc.state, sc.area
    for s in range(area.shape[0]):
        a = body[s, 0]
        b = body[s, 1]
        rax, ray, raz = body_vec(R, a, lever[s, 0, 0], lever[s, 0, 1], lever[s, 0, 2])
        rbx, rby, rbz = body_vec(R, b, lever[s, 1, 0], lever[s, 1, 1], lever[s, 1, 2])
        rx = (v[b, 0] + om[b, 1] * rbz - om[b, 2] * rby) - (v[a, 0] + om[a, 1] * raz - om[a, 2] * ray)
        ry = (v[b, 1] + om[b, 2] * rbx - om[b, 0] * rbz) - (v[a, 1] + om[a, 2] * rax - om[a, 0] * raz)
        rz = (v[b, 2] + om[b, 0] * rby - om[b, 1] * rbx) - (v[a, 2] + om[a, 0] * ray - om[a, 1] * rax)
        if large:
            nx, ny, nz = body_vec(R, a, axes[s, 0], axes[s, 1], axes[s, 2])
            ax, ay, az = body_vec(R, a, axes[s, 3], axes[s, 4], axes[s, 5])
            bx, by, bz = body_vec(R, a, axes[s, 6], axes[s, 7], axes[s, 8])
        else:
            nx, ny, nz = axes[s, 0], axes[s, 1], axes[s, 2]
            ax, ay, az = axes[s, 3], axes[s, 4], axes[s, 5]
            bx, by, bz = axes[s, 6], axes[s, 7], axes[s, 8]
        dun, dus1, dus2 = local_increments(dt, rx, ry, rz, nx, ny, nz, ax, ay, az, bx, by, bz)
        subcontact_law(jlaw, s, dun, dus1, dus2, jp, js)
        fx, fy, fz = traction_force(s, js, area, nx, ny, nz, ax, ay, az, bx, by, bz)
        add_force(f, mom, a, rax, ray, raz, fx, fy, fz)
        add_force(f, mom, b, rbx, rby, rbz, -fx, -fy, -fz)


def contact_forces(jlaw, rigid, large, dt, nodes, bodies, sc):
    """Adds the forces of the sub-contacts ``sc`` under the law ``jlaw`` to
    nodes.f (and, for rigid blocks, their moments to bodies.mom); ``jlaw``
    and ``rigid`` are literals (static.py)."""
    raise TypeError("contact_forces: only callable from compiled code")


@overload(contact_forces, prefer_literal=True)
def _contact_forces(jlaw, rigid, large, dt, nodes, bodies, sc):
    if choose({0: False, 1: True}, rigid, "rigid"):
        return lambda jlaw, rigid, large, dt, nodes, bodies, sc: _rigid_contacts(jlaw, large, dt, nodes, bodies, sc)
    return lambda jlaw, rigid, large, dt, nodes, bodies, sc: _deformable_contacts(jlaw, dt, nodes, sc)
