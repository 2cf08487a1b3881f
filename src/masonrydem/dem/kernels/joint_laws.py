"""Joint (contact) laws: the traction of one sub-contact (joints.py
applies them to the sub-contacts).

A joint law is a pure function law(p, st, dun, dus1, dus2) -> st': p the
sub-contact's parameters (a tuple laid out as the columns JP_*), st its
state (tractions sigma_n (tension positive), tau_1, tau_2, then the law's
state, as the columns JS_*), du_n (opening positive) and du_s the relative
displacement increments in the two tangent directions; it returns the new
state.  ``joint_law`` dispatches on the law id (laws.py holds the table of
laws).  (Pure functions of scalars: an inlined function that took the
arrays and branched kept numba's reference counting in the loop, 2.3
times the cost.)
"""
import math

from numba import njit
from numba.extending import overload

from .layout import (JOINT_BEARING, JOINT_BRITTLE_COULOMB, JOINT_COUPLED, JOINT_COUPLED_ADDITIVE,
                     JOINT_COUPLED_EXPONENTIAL, JOINT_COUPLED_FRICTION_SLIP, JOINT_COUPLED_TOTAL_SLIP, JOINT_ELASTIC,
                     JOINT_FRICTION, JP_C, JP_FT, JP_KN, JP_KS, JP_SU, JP_TANPHI, JP_TANPHI_R, JP_TANPSI, JP_WU, JS_D,
                     JS_SN, JS_SP, JS_T1, JS_T2, JS_WP)
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
