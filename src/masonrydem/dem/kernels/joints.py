"""Joint (contact) laws and the forces of the sub-contacts.

A joint law is a pure function law(p, st, dun, dus1, dus2) -> st': p the
sub-contact's parameters (a tuple laid out as the columns JP_*), st its
state (tractions sigma_n (tension positive), tau_1, tau_2, then the law's
state, as the columns JS_*), du_n (opening positive) and du_s the relative
displacement increments in the two tangent directions; it returns the new
state.  ``joint_law`` dispatches on the law id (laws.py holds the table of
laws).  (Pure functions of scalars: an inlined function that took the
arrays and branched kept numba's reference counting in the loop, 2.3
times the cost.)  Deformable and rigid blocks differ only in how a
sub-contact's relative velocity is gathered and its force spread.
"""
import math

from numba import njit
from numba.extending import overload

from .layout import (JOINT_BEARING, JOINT_BRITTLE_COULOMB, JOINT_COUPLED, JOINT_COUPLED_ADDITIVE,
                     JOINT_COUPLED_EXPONENTIAL, JOINT_COUPLED_FRICTION_SLIP, JOINT_COUPLED_TOTAL_SLIP, JOINT_ELASTIC,
                     JOINT_FRICTION, JP_C, JP_FT, JP_KN, JP_KS, JP_SU, JP_TANPHI, JP_TANPHI_R, JP_TANPSI, JP_WU, JS_D,
                     JS_SN, JS_SP, JS_T1, JS_T2, JS_WP)
from .linalg import add_force, body_vec
from .static import choose

_INLINE = dict(cache=True, inline="always", error_model="numpy")


@njit(**_INLINE)
def joint_elastic(p, st, dun, dus1, dus2):
    """Linear springs: sigma_n += k_n du_n, tau += k_s du_s."""
    return (st[JS_SN] + p[JP_KN] * dun, st[JS_T1] + p[JP_KS] * dus1, st[JS_T2] + p[JP_KS] * dus2,
            st[JS_WP], st[JS_SP], st[JS_D])


@njit(**_INLINE)
def _friction(p, st, sn, dus1, dus2):
    """Elastic trial tau += k_s du_s, then Coulomb friction
    |tau| <= -sigma_n tan(phi) (sigma_n <= 0): (tau_1, tau_2, the slip)."""
    ks = p[JP_KS]
    t1 = st[JS_T1] + ks * dus1
    t2 = st[JS_T2] + ks * dus2
    tmax = -sn * p[JP_TANPHI]
    tt = math.sqrt(t1 * t1 + t2 * t2)
    if tt > tmax:
        r = tmax / tt
        return t1 * r, t2 * r, (tt - tmax) / ks
    return t1, t2, 0.0


@njit(**_INLINE)
def joint_bearing(p, st, dun, dus1, dus2):
    """Rigid bearing strip: compression-only normal spring,
    sigma_n = min(0, sigma_n + k_n du_n), and Coulomb friction
    tau += k_s du_s, |tau| <= -sigma_n tan(phi) (a roller: k_s = tan(phi) = 0,
    and tau stays 0)."""
    sn = st[JS_SN] + p[JP_KN] * dun
    if sn > 0.0:
        sn = 0.0
    t1, t2, _ = _friction(p, st, sn, dus1, dus2)
    return sn, t1, t2, st[JS_WP], st[JS_SP], st[JS_D]


@njit(**_INLINE)
def _coulomb_return(p, st, dun, dus1, dus2):
    """Elastic trial, then tension cut-off and Coulomb slip with the current
    (damaged) strengths f_t' = f_t (1-D), c' = c (1-D) and friction
    tan(phi') = tan(phi) + D (tan(phi_r) - tan(phi)) (the residual friction),
    and dilation psi (a slip ds_p under compression presses the faces
    together: sigma_n -= k_n tan(psi) ds_p; 0 by default):
      sigma_n > f_t'  ->  sigma_n = f_t', w_p += excess opening;
      tau_max = max(0, c' - sigma_n tan(phi)); |tau| > tau_max -> scale tau
      back, s_p += excess slip.
    Returns (sigma_n, tau_1, tau_2, w_p, s_p, whether the joint yielded)."""
    kn = p[JP_KN]
    ks = p[JP_KS]
    dmg = st[JS_D]
    wp = st[JS_WP]
    sp = st[JS_SP]
    sn = st[JS_SN] + kn * dun
    t1 = st[JS_T1] + ks * dus1
    t2 = st[JS_T2] + ks * dus2
    ft = p[JP_FT] * (1.0 - dmg)
    c = p[JP_C] * (1.0 - dmg)
    yielded = False
    if sn > ft:
        wp += (sn - ft) / kn
        sn = ft
        yielded = True
    tmax = c - sn * (p[JP_TANPHI] + dmg * (p[JP_TANPHI_R] - p[JP_TANPHI]))
    if tmax < 0.0:
        tmax = 0.0
    tt = math.sqrt(t1 * t1 + t2 * t2)
    if tt > tmax:
        dsp = (tt - tmax) / ks
        sp += dsp
        r = tmax / tt
        t1 *= r
        t2 *= r
        yielded = True
        if sn < 0.0:
            sn -= kn * p[JP_TANPSI] * dsp
    return sn, t1, t2, wp, sp, yielded


@njit(**_INLINE)
def _softened(p, st, dun, dus1, dus2, shape, coupling, slip):
    """The coupled fracture-energy softening (docs/formulation.md, 4.3) and
    its variants (the model-form study), after ``_coulomb_return``: the
    relative openings x_t = w_p / w_u, w_u = 2 G_I / f_t, and slips
    x_s = s_p / s_u, s_u = 2 G_II / c (``slip`` 1: s_u = 2 G_II / (c -
    sigma_n tan(phi)), the peak's friction share in the slip scale; 2: the
    total slip s_p + |tau| / k_s, its elastic part too);
    ``shape`` 0 linear, d = min(x, 1), 1 exponential, d = 1 - exp(-2 x)
    (the same fracture energy); ``coupling`` 0 D = 1 - (1 - d_t)(1 - d_s),
    1 (Lourenco-Rots: one softening parameter for both strengths)
    D = min(x_t + x_s, 1).  D never decreases."""
    sn, t1, t2, wp, sp, yielded = _coulomb_return(p, st, dun, dus1, dus2)
    d = st[JS_D]
    if yielded:
        wu = p[JP_WU]
        su = p[JP_SU]
        if slip == 1 and sn < 0.0 and su > 0.0:
            su = su * p[JP_C] / (p[JP_C] - sn * p[JP_TANPHI])
        xt = 1.0
        if wu > 0.0:
            xt = min(wp / wu, 1.0)
        elif wp == 0.0:
            xt = 0.0
        if slip == 2:
            sp_ = sp + math.sqrt(t1 * t1 + t2 * t2) / p[JP_KS]
        else:
            sp_ = sp
        xs = 1.0
        if su > 0.0:
            xs = min(sp_ / su, 1.0)
        elif sp_ == 0.0:
            xs = 0.0
        if shape == 1:
            if wu > 0.0:
                xt = wp / wu
            if su > 0.0:
                xs = sp_ / su
            dn = 1.0 - math.exp(-2.0 * (xt + xs))
        elif coupling == 1:
            dn = min(xt + xs, 1.0)
        else:
            dn = 1.0 - (1.0 - xt) * (1.0 - xs)
        if dn > d:
            d = dn
    return sn, t1, t2, wp, sp, d


@njit(**_INLINE)
def joint_coupled(p, st, dun, dus1, dus2):
    """Coupled fracture-energy softening (docs/formulation.md, 4.3):
    d_t = w_p / w_u, w_u = 2 G_I / f_t;  d_s = s_p / s_u, s_u = 2 G_II / c;
    D = 1 - (1 - d_t)(1 - d_s), never decreasing, at most 1.  Linear
    softening of f_t and c with a shared damage; friction from tan(phi) to
    tan(phi_r) with D (equal by default); unloading elastic with the
    initial stiffness."""
    return _softened(p, st, dun, dus1, dus2, 0, 0, 0)


@njit(**_INLINE)
def joint_coupled_exponential(p, st, dun, dus1, dus2):
    """As ``joint_coupled`` with exponential softening, d = 1 - exp(-2 x):
    f_t exp(-f_t w_p / G_I) dissipates G_I (either coupling: the product of
    exponentials is the exponential of the sum)."""
    return _softened(p, st, dun, dus1, dus2, 1, 0, 0)


@njit(**_INLINE)
def joint_coupled_additive(p, st, dun, dus1, dus2):
    """As ``joint_coupled`` with Lourenco and Rots's coupling: f_t and c
    soften together through one parameter, the sum of the relative opening
    and slip, D = min(w_p / w_u + s_p / s_u, 1)."""
    return _softened(p, st, dun, dus1, dus2, 0, 1, 0)


@njit(**_INLINE)
def joint_coupled_friction_slip(p, st, dun, dus1, dus2):
    """As ``joint_coupled`` with the slip scale taken over the whole peak,
    cohesion and friction: s_u = 2 G_II / (c - sigma_n tan(phi))."""
    return _softened(p, st, dun, dus1, dus2, 0, 0, 1)


@njit(**_INLINE)
def joint_brittle_coulomb(p, st, dun, dus1, dus2):
    """Brittle Coulomb with tension cut-off: at the first yield in tension
    or shear, f_t and c drop to zero (D = 1); friction remains."""
    sn, t1, t2, wp, sp, yielded = _coulomb_return(p, st, dun, dus1, dus2)
    return sn, t1, t2, wp, sp, 1.0 if yielded else st[JS_D]


@njit(**_INLINE)
def joint_friction(p, st, dun, dus1, dus2):
    """Dry contact: no tension, no cohesion, Coulomb friction, and a gap.
    The total normal displacement e = w_p + sigma_n / k_n (opening
    positive) is tracked: e > 0 is an open gap (w_p = e, sigma_n = 0, no
    shear), e < 0 a penetration (sigma_n = k_n e).  Unlike the laws above,
    whose unloading is elastic from wherever the joint stands, a joint that
    opened must close its gap before it carries compression again (a
    rocking block lifts off and lands).  Shear: elastic trial
    tau += k_s du_s, |tau| <= -sigma_n tan(phi), excess slip into s_p."""
    kn = p[JP_KN]
    e = st[JS_WP] + st[JS_SN] / kn + dun
    if e > 0.0:
        wp = e
        sn = 0.0
    else:
        wp = 0.0
        sn = kn * e
    t1, t2, dsp = _friction(p, st, sn, dus1, dus2)
    return sn, t1, t2, wp, st[JS_SP] + dsp, st[JS_D]


@njit(**_INLINE)
def joint_coupled_total_slip(p, st, dun, dus1, dus2):
    """As ``joint_coupled`` with shear softening over the total slip,
    elastic and plastic: d_s = (s_p + |tau| / k_s) / s_u."""
    return _softened(p, st, dun, dus1, dus2, 0, 0, 2)


_JOINT_LAWS = {JOINT_ELASTIC: joint_elastic, JOINT_BRITTLE_COULOMB: joint_brittle_coulomb, JOINT_COUPLED: joint_coupled,
               JOINT_FRICTION: joint_friction, JOINT_BEARING: joint_bearing,
               JOINT_COUPLED_EXPONENTIAL: joint_coupled_exponential, JOINT_COUPLED_ADDITIVE: joint_coupled_additive,
               JOINT_COUPLED_FRICTION_SLIP: joint_coupled_friction_slip,
               JOINT_COUPLED_TOTAL_SLIP: joint_coupled_total_slip}


def joint_law(jlaw, p, st, dun, dus1, dus2):
    """The law ``jlaw`` (a literal id, chosen when the caller compiles:
    static.py) on one sub-contact's parameters and state."""
    raise TypeError("joint_law: only callable from compiled code")


@overload(joint_law, prefer_literal=True, inline="always")
def _joint_law(jlaw, p, st, dun, dus1, dus2):
    law = choose(_JOINT_LAWS, jlaw, "the joint law")
    return lambda jlaw, p, st, dun, dus1, dus2: law(p, st, dun, dus1, dus2)


@njit(**_INLINE)
def local_increments(dt, rx, ry, rz, nx, ny, nz, ax, ay, az, bx, by, bz):
    """du = dt (v_B - v_A), v_B - v_A = (rx, ry, rz), in the local axes
    n (A to B), t1, t2: (du_n, du_s1, du_s2)."""
    return dt * (rx * nx + ry * ny + rz * nz), dt * (rx * ax + ry * ay + rz * az), dt * (rx * bx + ry * by + rz * bz)


@njit(**_INLINE)
def subcontact_law(jlaw, s, dun, dus1, dus2, jp, js):
    """The law ``jlaw`` on sub-contact s under the local displacement
    increments: reads its parameters and state, writes its new state (the
    law's branches are in a function of scalars)."""
    p = (jp[s, 0], jp[s, 1], jp[s, 2], jp[s, 3], jp[s, 4], jp[s, 5], jp[s, 6], jp[s, 7], jp[s, 8])
    st = (js[s, 0], js[s, 1], js[s, 2], js[s, 3], js[s, 4], js[s, 5])
    sn, t1, t2, wp, sp, d = joint_law(jlaw, p, st, dun, dus1, dus2)
    js[s, JS_SN] = sn
    js[s, JS_T1] = t1
    js[s, JS_T2] = t2
    js[s, JS_WP] = wp
    js[s, JS_SP] = sp
    js[s, JS_D] = d


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


@njit(**_INLINE)
def _deformable_contacts(jlaw, dt, nodes, sc):
    """Deformable blocks, every lane: the sub-contact's point moves with
    the nodes of each side, interpolated with the weights w[s]; its force
    is spread with the same weights (so the virtual work is consistent).
    ``dt`` (S,): each lane's step.

    Four loops over the sub-contacts: (1) each gathers its relative
    velocity from the used slots of each side (cnt: a slot left out has
    weight 0 and adds exactly nothing), a node's S lanes one contiguous
    vector, and stores its displacement increments (in the work space
    ``force``, row s S + b); (2) the law over every sub-contact and lane,
    with no indirect access: over the Fortran-ordered parameters and state
    numba emits vector code; (3) each stores its force; (4) each node
    gathers the forces of its sub-contacts (``contacts.with_gather``), in
    sub-contact order.  Each lane's values are those of one loop that runs
    the law and scatters each force to its nodes, bit for bit (the vector
    code does the same IEEE operations lane by lane)."""
    v = nodes.v
    nl = v.shape[2]
    w, ix, axes, cnt = sc.w, sc.nodes, sc.axes, sc.cnt
    jp, js, area, work = sc.par, sc.state, sc.area, sc.force
    n = area.shape[0]
    for s in range(n):
        r0 = s * nl
        for b in range(nl):
            work[r0 + b, 0] = 0.0
            work[r0 + b, 1] = 0.0
            work[r0 + b, 2] = 0.0
        for k in range(cnt[s, 0]):
            nd = ix[s, k]
            wk = w[s, k]
            for b in range(nl):
                work[r0 + b, 0] -= wk * v[nd, 0, b]
                work[r0 + b, 1] -= wk * v[nd, 1, b]
                work[r0 + b, 2] -= wk * v[nd, 2, b]
        for k in range(4, 4 + cnt[s, 1]):
            nd = ix[s, k]
            wk = w[s, k]
            for b in range(nl):
                work[r0 + b, 0] += wk * v[nd, 0, b]
                work[r0 + b, 1] += wk * v[nd, 1, b]
                work[r0 + b, 2] += wk * v[nd, 2, b]
        nx, ny, nz, ax, ay, az = axes[s, 0], axes[s, 1], axes[s, 2], axes[s, 3], axes[s, 4], axes[s, 5]
        bx, by, bz = axes[s, 6], axes[s, 7], axes[s, 8]
        for b in range(nl):
            work[r0 + b, 0], work[r0 + b, 1], work[r0 + b, 2] = local_increments(
                dt[b], work[r0 + b, 0], work[r0 + b, 1], work[r0 + b, 2], nx, ny, nz, ax, ay, az, bx, by, bz)
    for i in range(n * nl):
        subcontact_law(jlaw, i, work[i, 0], work[i, 1], work[i, 2], jp, js)
    for s in range(n):
        r0 = s * nl
        ar = area[s]
        nx, ny, nz, ax, ay, az = axes[s, 0], axes[s, 1], axes[s, 2], axes[s, 3], axes[s, 4], axes[s, 5]
        bx, by, bz = axes[s, 6], axes[s, 7], axes[s, 8]
        for b in range(nl):
            sn = js[r0 + b, JS_SN]
            s1 = js[r0 + b, JS_T1]
            s2 = js[r0 + b, JS_T2]
            work[r0 + b, 0] = ar * (sn * nx + s1 * ax + s2 * bx)
            work[r0 + b, 1] = ar * (sn * ny + s1 * ay + s2 * by)
            work[r0 + b, 2] = ar * (sn * nz + s1 * az + s2 * bz)
    gather_forces(nodes.f, sc.gptr, sc.gs, sc.gw, work)


@njit(**_INLINE)
def gather_forces(f, gptr, gs, gw, force):
    """f[i] += sum_j gw[j] force[gs[j]] over j in gptr[i]:gptr[i + 1], in
    that order (``contacts.with_gather``), in every lane: f (n, 3, S),
    force row s S + b."""
    nl = f.shape[2]
    for i in range(gptr.shape[0] - 1):
        j0 = gptr[i]
        j1 = gptr[i + 1]
        for j in range(j0, j1):
            r0 = gs[j] * nl
            wj = gw[j]
            for b in range(nl):
                f[i, 0, b] += wj * force[r0 + b, 0]
                f[i, 1, b] += wj * force[r0 + b, 1]
                f[i, 2, b] += wj * force[r0 + b, 2]


@njit(**_INLINE)
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
