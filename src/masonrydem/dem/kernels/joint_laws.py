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

The laws compute both sides of each of their cases and then pick one
(``a if case else b`` of two values already computed), so that a loop of
them over sub-contacts, or over the lanes of a batch, is straight-line
code that LLVM vectorises: the same IEEE operations on each value, and so
the same bits, as a law that branched (a value computed for the case not
taken, such as a division by a zero scale, is discarded).  Where many
sub-contacts yield, whose branches a scalar law mispredicts, that halves
their cost (`make bench`, every sub-contact yielding: 8.1 -> 3.7 ns a
sub-contact-sample at 8 lanes); where they stay elastic it gains little.
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
    r = tmax / tt
    slip = (tt - tmax) / ks
    t1r = t1 * r
    t2r = t2 * r
    over = tt > tmax
    return t1r if over else t1, t2r if over else t2, slip if over else 0.0


@njit(**_INLINE)
def joint_bearing(p, st, dun, dus1, dus2):
    """Rigid bearing strip: compression-only normal spring,
    sigma_n = min(0, sigma_n + k_n du_n), and Coulomb friction
    tau += k_s du_s, |tau| <= -sigma_n tan(phi) (a roller: k_s = tan(phi) = 0,
    and tau stays 0)."""
    sn = st[JS_SN] + p[JP_KN] * dun
    sn = 0.0 if sn > 0.0 else sn
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
    cut = sn > ft
    wp_cut = wp + (sn - ft) / kn
    wp = wp_cut if cut else wp
    sn = ft if cut else sn
    tmax = c - sn * (p[JP_TANPHI] + dmg * (p[JP_TANPHI_R] - p[JP_TANPHI]))
    tmax = 0.0 if tmax < 0.0 else tmax
    tt = math.sqrt(t1 * t1 + t2 * t2)
    slip = tt > tmax
    dsp = (tt - tmax) / ks
    r = tmax / tt
    sp_slip = sp + dsp
    t1_slip = t1 * r
    t2_slip = t2 * r
    sn_slip = sn - kn * p[JP_TANPSI] * dsp
    sp = sp_slip if slip else sp
    t1 = t1_slip if slip else t1
    t2 = t2_slip if slip else t2
    sn = sn_slip if slip & (sn < 0.0) else sn
    return sn, t1, t2, wp, sp, cut | slip


@njit(**_INLINE)
def _relative(x, u):
    """min(x / u, 1) for a scale u > 0; for u = 0 (no softening), 0 while x
    is 0, else 1."""
    xu = min(x / u, 1.0)
    x0 = 0.0 if x == 0.0 else 1.0
    return xu if u > 0.0 else x0


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
    D = min(x_t + x_s, 1).  D never decreases, and grows only where the
    joint yielded."""
    sn, t1, t2, wp, sp, yielded = _coulomb_return(p, st, dun, dus1, dus2)
    d = st[JS_D]
    wu = p[JP_WU]
    su = p[JP_SU]
    if slip == 1:
        su_peak = su * p[JP_C] / (p[JP_C] - sn * p[JP_TANPHI])
        su = su_peak if (sn < 0.0) & (su > 0.0) else su
    sp_ = sp
    if slip == 2:
        sp_ = sp + math.sqrt(t1 * t1 + t2 * t2) / p[JP_KS]
    xt = _relative(wp, wu)
    xs = _relative(sp_, su)
    if shape == 1:
        xt_e = wp / wu
        xs_e = sp_ / su
        xt = xt_e if wu > 0.0 else xt
        xs = xs_e if su > 0.0 else xs
        dn = 1.0 - math.exp(-2.0 * (xt + xs))
    elif coupling == 1:
        dn = min(xt + xs, 1.0)
    else:
        dn = 1.0 - (1.0 - xt) * (1.0 - xs)
    d = dn if yielded & (dn > d) else d
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
    sn_closed = kn * e
    wp = e if e > 0.0 else 0.0
    sn = 0.0 if e > 0.0 else sn_closed
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
