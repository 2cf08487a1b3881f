"""Hot kernels: every jitted function of the solver lives here.

numba's on-disk cache does not notice edits in *other* modules that a jitted
function calls (numba issue 1833), so the constitutive laws and the time-step
kernels are kept together in this one module.

Conventions
-----------
* SI units, tension positive for zone stresses and joint normal stresses.
* Zone stress components are stored as (xx, yy, zz, xy, yz, zx).
* Constitutive laws are small inlined functions behind one signature per kind
  (zone law, joint law).  The kernels are specialised on a *literal* law id
  (``numba.literally``), so a model compiles and runs only the laws it uses,
  and the on-disk cache keeps one entry per law actually used.

Zone law ids:   ZONE_ELASTIC, ZONE_MOHR_COULOMB
Joint law ids:  JOINT_ELASTIC, JOINT_BRITTLE_COULOMB, JOINT_COUPLED, JOINT_BEARING,
                JOINT_FRICTION
"""
import math

import numpy as np
from numba import literally, njit

ZONE_ELASTIC = 0
ZONE_MOHR_COULOMB = 1

JOINT_ELASTIC = 0
JOINT_BRITTLE_COULOMB = 1
JOINT_COUPLED = 2
JOINT_BEARING = 3
JOINT_FRICTION = 4

# --- zone material parameter / state columns -------------------------------
# zone params (per tetrahedron)
ZP_K, ZP_G, ZP_FT, ZP_C, ZP_NPHI, ZP_GF = 0, 1, 2, 3, 4, 5
N_ZP = 6
# zone state (per tetrahedron)
ZS_EPT, ZS_EULT, ZS_H = 0, 1, 2  # plastic tensile strain, ultimate, crack band
N_ZS = 3

# --- joint parameter / state columns ----------------------------------------
JP_KN, JP_KS, JP_FT, JP_C, JP_TANPHI, JP_WU, JP_SU = 0, 1, 2, 3, 4, 5, 6
N_JP = 7
JS_SN, JS_T1, JS_T2, JS_WP, JS_SP, JS_D = 0, 1, 2, 3, 4, 5
N_JS = 6

# status codes returned by the chunk kernel
ST_OK = 0
ST_NONFINITE = 1

_CACHE = dict(cache=True, nogil=True, error_model="numpy")
_INLINE = dict(cache=True, inline="always", error_model="numpy")


# =============================================================================
# Small linear algebra
# =============================================================================
@njit(**_INLINE)
def _rotate(a, v, p, q):
    """One Jacobi rotation zeroing a[p, q] of the symmetric 3x3 ``a``;
    accumulates the rotation into the eigenvector matrix ``v`` (columns)."""
    apq = a[p, q]
    if apq == 0.0:
        return
    theta = (a[q, q] - a[p, p]) / (2.0 * apq)
    t = 1.0 / (abs(theta) + math.sqrt(theta * theta + 1.0))
    if theta < 0.0:
        t = -t
    c = 1.0 / math.sqrt(t * t + 1.0)
    s = t * c
    for k in range(3):
        akp = a[k, p]
        akq = a[k, q]
        a[k, p] = c * akp - s * akq
        a[k, q] = s * akp + c * akq
    for k in range(3):
        apk = a[p, k]
        aqk = a[q, k]
        a[p, k] = c * apk - s * aqk
        a[q, k] = s * apk + c * aqk
    for k in range(3):
        vkp = v[k, p]
        vkq = v[k, q]
        v[k, p] = c * vkp - s * vkq
        v[k, q] = s * vkp + c * vkq


@njit(**_INLINE)
def eig_sym3(s0, s1, s2, s3, s4, s5, a, v):
    """Eigen-decomposition of the symmetric tensor (xx,yy,zz,xy,yz,zx) by
    cyclic Jacobi rotations (Golub & Van Loan, sec. 8.5).  On return the
    diagonal of ``a`` holds the eigenvalues and the columns of ``v`` the unit
    eigenvectors.  ``a`` and ``v`` are 3x3 scratch arrays."""
    a[0, 0] = s0
    a[1, 1] = s1
    a[2, 2] = s2
    a[0, 1] = s3
    a[1, 0] = s3
    a[1, 2] = s4
    a[2, 1] = s4
    a[0, 2] = s5
    a[2, 0] = s5
    for i in range(3):
        for j in range(3):
            v[i, j] = 1.0 if i == j else 0.0
    scale = abs(s0) + abs(s1) + abs(s2) + abs(s3) + abs(s4) + abs(s5)
    if scale == 0.0:
        return
    for _sweep in range(12):
        off = abs(a[0, 1]) + abs(a[1, 2]) + abs(a[0, 2])
        if off <= 1e-15 * scale:
            break
        _rotate(a, v, 0, 1)
        _rotate(a, v, 1, 2)
        _rotate(a, v, 0, 2)


# =============================================================================
# Zone (block material) laws
#
# Every zone first takes the elastic trial (zone_elastic); a plastic law then
# corrects stress[t] in place and updates its state zs[t].
# =============================================================================
@njit(**_INLINE)
def zone_elastic(t, d0, d1, d2, d3, d4, d5, zp, stress):
    """Isotropic linear elasticity, incremental form:
    dsigma = 2 G de + (K - 2G/3) tr(de) I."""
    g2 = 2.0 * zp[t, ZP_G]
    lam = zp[t, ZP_K] - g2 / 3.0
    ev = d0 + d1 + d2
    stress[t, 0] += g2 * d0 + lam * ev
    stress[t, 1] += g2 * d1 + lam * ev
    stress[t, 2] += g2 * d2 + lam * ev
    stress[t, 3] += g2 * d3
    stress[t, 4] += g2 * d4
    stress[t, 5] += g2 * d5


@njit(**_INLINE)
def tensile_strength(ft, ept, eult):
    """Linear tension softening: sigma_t = f_t (1 - e_pt / e_ult), >= 0;
    e_ult = 2 G_f / (f_t h) (crack band, Bazant & Oh 1983)."""
    if eult <= 0.0:
        return ft
    r = 1.0 - ept / eult
    return ft * r if r > 0.0 else 0.0


@njit(**_INLINE)
def mohr_coulomb_elastic(t, zp, zs, stress):
    """Cheap test that a trial stress is inside the Mohr-Coulomb surface with
    tension cut-off, with bounds on the extreme principal stresses: for the
    deviator |s_i| <= 2 sqrt(J2/3), so s3 <= p + 2 sqrt(J2/3) and
    s1 >= p - 2 sqrt(J2/3).  Only zones failing it pay for the
    eigen-decomposition of ``zone_mohr_coulomb``."""
    s0 = stress[t, 0]
    s1_ = stress[t, 1]
    s2_ = stress[t, 2]
    s3_ = stress[t, 3]
    s4_ = stress[t, 4]
    s5_ = stress[t, 5]
    nphi = zp[t, ZP_NPHI]
    sig_t = tensile_strength(zp[t, ZP_FT], zs[t, ZS_EPT], zs[t, ZS_EULT])
    p = (s0 + s1_ + s2_) / 3.0
    dx = s0 - p
    dy = s1_ - p
    dz = s2_ - p
    j2 = 0.5 * (dx * dx + dy * dy + dz * dz) + s3_ * s3_ + s4_ * s4_ + s5_ * s5_
    r = 2.0 * math.sqrt(j2 / 3.0)
    return p + r <= sig_t and (p - r) - (p + r) * nphi + 2.0 * zp[t, ZP_C] * math.sqrt(nphi) >= 0.0


@njit(**_INLINE)
def zone_mohr_coulomb(t, zp, zs, stress, a, v, x0, gnodes, k0, k1):
    """Mohr-Coulomb with tension cut-off on the elastic trial ``stress[t]``
    (Itasca FLAC3D formulation, principal stresses s1 <= s2 <= s3, tension
    positive):

        f_s = s1 - s3 N_phi + 2 c sqrt(N_phi)      (shear failure if < 0)
        f_t = sigma_t - s3                         (tension failure if < 0)

    Shear: perfectly plastic, non-associated with zero dilation (N_psi = 1):
        lambda = f_s / (2G (1 + N_phi)),  s1 -= 2G lambda,  s3 += 2G lambda.
    Tension: associated, lambda = (s3 - sigma_t)/alpha1, s3 = sigma_t,
        s1, s2 -= lambda alpha2, plastic tensile strain e_pt += lambda; the
        tensile strength softens linearly to zero at
        e_ult = 2 G_f / (f_t h), with h the width of the zone's cell (its
        mixed-discretization overlay, i.e. the hexahedral cell, or the
        tetrahedron itself) measured along the crack normal (the s3
        direction) when the zone first cracks.
    The region is chosen with FLAC's h-function
        h = s3 - sigma_t + alpha_P (s1 - sigma_P),
        alpha_P = sqrt(1 + N_phi^2) + N_phi, sigma_P = sigma_t N_phi - 2c sqrt(N_phi).
    Returns True if the stress was corrected (the zone yielded)."""
    c = zp[t, ZP_C]
    nphi = zp[t, ZP_NPHI]
    sqn = math.sqrt(nphi)
    sig_t = tensile_strength(zp[t, ZP_FT], zs[t, ZS_EPT], zs[t, ZS_EULT])
    eig_sym3(stress[t, 0], stress[t, 1], stress[t, 2], stress[t, 3], stress[t, 4],
             stress[t, 5], a, v)
    # sort principal values ascending, remembering their columns
    i1, i2, i3 = 0, 1, 2
    if a[i1, i1] > a[i2, i2]:
        i1, i2 = i2, i1
    if a[i2, i2] > a[i3, i3]:
        i2, i3 = i3, i2
    if a[i1, i1] > a[i2, i2]:
        i1, i2 = i2, i1
    p1 = a[i1, i1]
    p3 = a[i3, i3]
    fs = p1 - p3 * nphi + 2.0 * c * sqn
    if fs >= 0.0 and p3 <= sig_t:
        return False     # the pre-check was conservative: no yield
    kk = zp[t, ZP_K]
    g = zp[t, ZP_G]
    alpha1 = kk + 4.0 * g / 3.0
    alpha2 = kk - 2.0 * g / 3.0
    alpha_p = math.sqrt(1.0 + nphi * nphi) + nphi
    sigma_p = sig_t * nphi - 2.0 * c * sqn
    hf = p3 - sig_t + alpha_p * (p1 - sigma_p)
    d1 = 0.0
    d2 = 0.0
    d3 = 0.0
    if fs < 0.0 and hf <= 0.0:
        lam = fs / (2.0 * g * (1.0 + nphi))
        d1 = -2.0 * g * lam
        d3 = 2.0 * g * lam
    elif p3 > sig_t:
        lam = (p3 - sig_t) / alpha1
        d1 = -lam * alpha2
        d2 = -lam * alpha2
        d3 = sig_t - p3
        if zs[t, ZS_EULT] == 0.0:
            # crack onset: crack band width of the cell along the s3 direction
            nx = v[0, i3]
            ny = v[1, i3]
            nz = v[2, i3]
            lo = 1e300
            hi = -1e300
            for k in range(k0, k1):
                nd = gnodes[k]
                q = x0[nd, 0] * nx + x0[nd, 1] * ny + x0[nd, 2] * nz
                lo = min(lo, q)
                hi = max(hi, q)
            h = hi - lo
            zs[t, ZS_H] = h
            zs[t, ZS_EULT] = 2.0 * zp[t, ZP_GF] / (zp[t, ZP_FT] * h)
        zs[t, ZS_EPT] += lam
    else:
        return False
    # stress correction: sum_i d_i n_i n_i^T
    for (di, col) in ((d1, i1), (d2, i2), (d3, i3)):
        if di != 0.0:
            nx = v[0, col]
            ny = v[1, col]
            nz = v[2, col]
            stress[t, 0] += di * nx * nx
            stress[t, 1] += di * ny * ny
            stress[t, 2] += di * nz * nz
            stress[t, 3] += di * nx * ny
            stress[t, 4] += di * ny * nz
            stress[t, 5] += di * nz * nx
    return True


# =============================================================================
# Zone kernel: strain rates, mixed discretization, stresses, nodal forces
# =============================================================================
@njit(**_INLINE)
def _tet_forces(t, w, sxx, syy, szz, sxy, syz, szx, tets, dn, f):
    """f_a -= w V sigma . grad N_a for the 4 nodes of tetrahedron t
    (``w`` = weight * volume); grad N_0 = -(grad N_1 + grad N_2 + grad N_3)."""
    sxx *= w
    syy *= w
    szz *= w
    sxy *= w
    syz *= w
    szx *= w
    f1x = sxx * dn[t, 0] + sxy * dn[t, 1] + szx * dn[t, 2]
    f1y = sxy * dn[t, 0] + syy * dn[t, 1] + syz * dn[t, 2]
    f1z = szx * dn[t, 0] + syz * dn[t, 1] + szz * dn[t, 2]
    f2x = sxx * dn[t, 3] + sxy * dn[t, 4] + szx * dn[t, 5]
    f2y = sxy * dn[t, 3] + syy * dn[t, 4] + syz * dn[t, 5]
    f2z = szx * dn[t, 3] + syz * dn[t, 4] + szz * dn[t, 5]
    f3x = sxx * dn[t, 6] + sxy * dn[t, 7] + szx * dn[t, 8]
    f3y = sxy * dn[t, 6] + syy * dn[t, 7] + syz * dn[t, 8]
    f3z = szx * dn[t, 6] + syz * dn[t, 7] + szz * dn[t, 8]
    n0 = tets[t, 0]
    n1 = tets[t, 1]
    n2 = tets[t, 2]
    n3 = tets[t, 3]
    f[n1, 0] -= f1x
    f[n1, 1] -= f1y
    f[n1, 2] -= f1z
    f[n2, 0] -= f2x
    f[n2, 1] -= f2y
    f[n2, 2] -= f2z
    f[n3, 0] -= f3x
    f[n3, 1] -= f3y
    f[n3, 2] -= f3z
    f[n0, 0] += f1x + f2x + f3x
    f[n0, 1] += f1y + f2y + f3y
    f[n0, 2] += f1z + f2z + f3z


@njit(**_INLINE)
def zone_forces(zlaw, dt, v, f, x0, tets, dn, vol, wt, gptr, gnodes, gnptr,
                zp, zs, stress, de, ev_, pending, a, evec):
    """Adds the zones' nodal forces to ``f``.

    For each tetrahedron: grad v = sum_a v_a (x) grad N_a,
    de = dt/2 (grad v + grad v^T).  Mixed discretization (Marti & Cundall
    1982): within each group (an overlay of 5 tetrahedra of a hexahedral
    cell, or a single tetrahedron) the volumetric part of de is replaced by
    the volume-weighted mean of the group.  Nodal forces
    f_a -= w V sigma . grad N_a, with w = 1/2 for the two overlays of a cell.
    ``dn[t]`` holds grad N_1..N_3 (grad N_0 = -sum).

    Plastic laws run in a second pass: the first computes the elastic trial
    and its forces and queues (in ``pending``) the zones that may yield; the
    second corrects their stresses and adds the forces of the correction
    (forces are linear in the stress).  Keeping the rarely-taken return
    mapping out of the main loop keeps that loop fast."""
    ng = gptr.shape[0] - 1
    npend = 0
    for g in range(ng):
        t0 = gptr[g]
        t1 = gptr[g + 1]
        sv = 0.0
        sev = 0.0
        for t in range(t0, t1):
            n0 = tets[t, 0]
            n1 = tets[t, 1]
            n2 = tets[t, 2]
            n3 = tets[t, 3]
            # velocity differences relative to node 0
            ax = v[n1, 0] - v[n0, 0]
            ay = v[n1, 1] - v[n0, 1]
            az = v[n1, 2] - v[n0, 2]
            bx = v[n2, 0] - v[n0, 0]
            by = v[n2, 1] - v[n0, 1]
            bz = v[n2, 2] - v[n0, 2]
            cx = v[n3, 0] - v[n0, 0]
            cy = v[n3, 1] - v[n0, 1]
            cz = v[n3, 2] - v[n0, 2]
            g1x = dn[t, 0]
            g1y = dn[t, 1]
            g1z = dn[t, 2]
            g2x = dn[t, 3]
            g2y = dn[t, 4]
            g2z = dn[t, 5]
            g3x = dn[t, 6]
            g3y = dn[t, 7]
            g3z = dn[t, 8]
            lxx = ax * g1x + bx * g2x + cx * g3x
            lyy = ay * g1y + by * g2y + cy * g3y
            lzz = az * g1z + bz * g2z + cz * g3z
            lxy = ax * g1y + bx * g2y + cx * g3y
            lyx = ay * g1x + by * g2x + cy * g3x
            lyz = ay * g1z + by * g2z + cy * g3z
            lzy = az * g1y + bz * g2y + cz * g3y
            lzx = az * g1x + bz * g2x + cz * g3x
            lxz = ax * g1z + bx * g2z + cx * g3z
            k = t - t0
            de[k, 0] = dt * lxx
            de[k, 1] = dt * lyy
            de[k, 2] = dt * lzz
            de[k, 3] = 0.5 * dt * (lxy + lyx)
            de[k, 4] = 0.5 * dt * (lyz + lzy)
            de[k, 5] = 0.5 * dt * (lzx + lxz)
            ev = de[k, 0] + de[k, 1] + de[k, 2]
            ev_[k] = ev
            sv += vol[t]
            sev += vol[t] * ev
        evm = sev / sv
        for t in range(t0, t1):
            k = t - t0
            corr = (evm - ev_[k]) / 3.0
            zone_elastic(t, de[k, 0] + corr, de[k, 1] + corr, de[k, 2] + corr,
                         de[k, 3], de[k, 4], de[k, 5], zp, stress)
            if zlaw == ZONE_MOHR_COULOMB:
                if not mohr_coulomb_elastic(t, zp, zs, stress):
                    pending[npend, 0] = t
                    pending[npend, 1] = g
                    npend += 1
            _tet_forces(t, wt[t] * vol[t], stress[t, 0], stress[t, 1], stress[t, 2],
                        stress[t, 3], stress[t, 4], stress[t, 5], tets, dn, f)
    for i in range(npend):
        t = pending[i, 0]
        g = pending[i, 1]
        o0 = stress[t, 0]
        o1 = stress[t, 1]
        o2 = stress[t, 2]
        o3 = stress[t, 3]
        o4 = stress[t, 4]
        o5 = stress[t, 5]
        if zone_mohr_coulomb(t, zp, zs, stress, a, evec, x0, gnodes, gnptr[g], gnptr[g + 1]):
            _tet_forces(t, wt[t] * vol[t], stress[t, 0] - o0, stress[t, 1] - o1,
                        stress[t, 2] - o2, stress[t, 3] - o3, stress[t, 4] - o4,
                        stress[t, 5] - o5, tets, dn, f)


# =============================================================================
# Joint (contact) laws
#
# Signature: law(s, jp, js, dun, dus1, dus2) -> None.  Updates the tractions
# js[s, JS_SN] (tension positive), js[s, JS_T1], js[s, JS_T2] and the law's
# state from the relative displacement increments of sub-contact s
# (du_n opening positive, du_s in the two tangent directions).
# =============================================================================
@njit(**_INLINE)
def joint_elastic(s, jp, js, dun, dus1, dus2):
    """Linear springs: sigma_n += k_n du_n, tau += k_s du_s."""
    js[s, JS_SN] += jp[s, JP_KN] * dun
    js[s, JS_T1] += jp[s, JP_KS] * dus1
    js[s, JS_T2] += jp[s, JP_KS] * dus2


@njit(**_INLINE)
def joint_bearing(s, jp, js, dun, dus1, dus2):
    """Rigid bearing strip: compression-only normal spring, frictionless
    (a roller): sigma_n = min(0, sigma_n + k_n du_n), tau = 0."""
    sn = js[s, JS_SN] + jp[s, JP_KN] * dun
    js[s, JS_SN] = sn if sn < 0.0 else 0.0


@njit(**_INLINE)
def _coulomb_return(s, jp, js, dun, dus1, dus2):
    """Elastic trial, then tension cut-off and Coulomb slip with the current
    (damaged) strengths f_t' = f_t (1-D), c' = c (1-D):
      sigma_n > f_t'  ->  sigma_n = f_t', w_p += excess opening;
      tau_max = max(0, c' - sigma_n tan(phi)); |tau| > tau_max -> scale tau
      back, s_p += excess slip.
    Returns True if the joint yielded."""
    kn = jp[s, JP_KN]
    ks = jp[s, JP_KS]
    dmg = js[s, JS_D]
    sn = js[s, JS_SN] + kn * dun
    t1 = js[s, JS_T1] + ks * dus1
    t2 = js[s, JS_T2] + ks * dus2
    ft = jp[s, JP_FT] * (1.0 - dmg)
    c = jp[s, JP_C] * (1.0 - dmg)
    yielded = False
    if sn > ft:
        js[s, JS_WP] += (sn - ft) / kn
        sn = ft
        yielded = True
    tmax = c - sn * jp[s, JP_TANPHI]
    if tmax < 0.0:
        tmax = 0.0
    tt = math.sqrt(t1 * t1 + t2 * t2)
    if tt > tmax:
        js[s, JS_SP] += (tt - tmax) / ks
        r = tmax / tt
        t1 *= r
        t2 *= r
        yielded = True
    js[s, JS_SN] = sn
    js[s, JS_T1] = t1
    js[s, JS_T2] = t2
    return yielded


@njit(**_INLINE)
def joint_coupled(s, jp, js, dun, dus1, dus2):
    """Coupled fracture-energy softening (solver.md, Joints):
    d_t = w_p / w_u, w_u = 2 G_I / f_t;  d_s = s_p / s_u, s_u = 2 G_II / c;
    D = 1 - (1 - d_t)(1 - d_s), never decreasing, at most 1.  Linear
    softening of f_t and c with a shared damage; friction angle unchanged;
    unloading elastic with the initial stiffness."""
    if _coulomb_return(s, jp, js, dun, dus1, dus2):
        wu = jp[s, JP_WU]
        su = jp[s, JP_SU]
        dt_ = 1.0
        if wu > 0.0:
            dt_ = min(js[s, JS_WP] / wu, 1.0)
        elif js[s, JS_WP] == 0.0:
            dt_ = 0.0
        ds_ = 1.0
        if su > 0.0:
            ds_ = min(js[s, JS_SP] / su, 1.0)
        elif js[s, JS_SP] == 0.0:
            ds_ = 0.0
        d = 1.0 - (1.0 - dt_) * (1.0 - ds_)
        if d > js[s, JS_D]:
            js[s, JS_D] = d


@njit(**_INLINE)
def joint_brittle_coulomb(s, jp, js, dun, dus1, dus2):
    """Brittle Coulomb with tension cut-off: at the first yield in tension
    or shear, f_t and c drop to zero (D = 1); friction remains."""
    if _coulomb_return(s, jp, js, dun, dus1, dus2):
        js[s, JS_D] = 1.0


@njit(**_INLINE)
def joint_friction(s, jp, js, dun, dus1, dus2):
    """Dry contact: no tension, no cohesion, Coulomb friction, and a gap.
    The total normal displacement e = w_p + sigma_n / k_n (opening
    positive) is tracked: e > 0 is an open gap (w_p = e, sigma_n = 0, no
    shear), e < 0 a penetration (sigma_n = k_n e).  Unlike the laws above,
    whose unloading is elastic from wherever the joint stands, a joint that
    opened must close its gap before it carries compression again (a
    rocking block lifts off and lands).  Shear: elastic trial
    tau += k_s du_s, |tau| <= -sigma_n tan(phi), excess slip into s_p."""
    kn = jp[s, JP_KN]
    e = js[s, JS_WP] + js[s, JS_SN] / kn + dun
    if e > 0.0:
        js[s, JS_WP] = e
        js[s, JS_SN] = 0.0
    else:
        js[s, JS_WP] = 0.0
        js[s, JS_SN] = kn * e
    ks = jp[s, JP_KS]
    t1 = js[s, JS_T1] + ks * dus1
    t2 = js[s, JS_T2] + ks * dus2
    tmax = -js[s, JS_SN] * jp[s, JP_TANPHI]
    tt = math.sqrt(t1 * t1 + t2 * t2)
    if tt > tmax:
        js[s, JS_SP] += (tt - tmax) / ks
        r = tmax / tt if tt > 0.0 else 0.0
        t1 *= r
        t2 *= r
    js[s, JS_T1] = t1
    js[s, JS_T2] = t2


@njit(**_INLINE)
def contact_forces(jlaw, dt, v, f, nodes, cnt, w, axes, area, jp, js):
    """Adds the forces of the sub-contacts to ``f``.

    Sub-contact s joins side A (nodes[s, 0:cnt[s,0]]) and side B
    (nodes[s, 4:4+cnt[s,1]]) at one point, interpolated with the weights
    w[s]; axes[s] = (n, t1, t2) with n pointing from A to B.  Relative
    velocity v_B - v_A gives du = dt (v_B - v_A) in local axes; the traction
    t = sigma_n n + tau_1 t1 + tau_2 t2 acts on A as +area t and on B as
    -area t, spread with the same weights (so the virtual work is
    consistent)."""
    for s in range(area.shape[0]):
        rx = 0.0
        ry = 0.0
        rz = 0.0
        for k in range(cnt[s, 0]):
            nd = nodes[s, k]
            wk = w[s, k]
            rx -= wk * v[nd, 0]
            ry -= wk * v[nd, 1]
            rz -= wk * v[nd, 2]
        for k in range(4, 4 + cnt[s, 1]):
            nd = nodes[s, k]
            wk = w[s, k]
            rx += wk * v[nd, 0]
            ry += wk * v[nd, 1]
            rz += wk * v[nd, 2]
        nx = axes[s, 0]
        ny = axes[s, 1]
        nz = axes[s, 2]
        ax = axes[s, 3]
        ay = axes[s, 4]
        az = axes[s, 5]
        bx = axes[s, 6]
        by = axes[s, 7]
        bz = axes[s, 8]
        dun = dt * (rx * nx + ry * ny + rz * nz)
        du1 = dt * (rx * ax + ry * ay + rz * az)
        du2 = dt * (rx * bx + ry * by + rz * bz)
        if jlaw == JOINT_ELASTIC:
            joint_elastic(s, jp, js, dun, du1, du2)
        elif jlaw == JOINT_BRITTLE_COULOMB:
            joint_brittle_coulomb(s, jp, js, dun, du1, du2)
        elif jlaw == JOINT_COUPLED:
            joint_coupled(s, jp, js, dun, du1, du2)
        elif jlaw == JOINT_FRICTION:
            joint_friction(s, jp, js, dun, du1, du2)
        elif jlaw == JOINT_BEARING:
            joint_bearing(s, jp, js, dun, du1, du2)
        sn = js[s, JS_SN]
        s1 = js[s, JS_T1]
        s2 = js[s, JS_T2]
        ar = area[s]
        fx = ar * (sn * nx + s1 * ax + s2 * bx)
        fy = ar * (sn * ny + s1 * ay + s2 * by)
        fz = ar * (sn * nz + s1 * az + s2 * bz)
        for k in range(cnt[s, 0]):
            nd = nodes[s, k]
            wk = w[s, k]
            f[nd, 0] += wk * fx
            f[nd, 1] += wk * fy
            f[nd, 2] += wk * fz
        for k in range(4, 4 + cnt[s, 1]):
            nd = nodes[s, k]
            wk = w[s, k]
            f[nd, 0] -= wk * fx
            f[nd, 1] -= wk * fy
            f[nd, 2] -= wk * fz


# =============================================================================
# Time stepping
# =============================================================================
@njit(**_INLINE)
def _advance_dof(i, d, fa, f, v, u, mass, fixed, vpres, vf, alpha, dt):
    """One translational component of node (or body) i: total force
    f[i, d] + fa (fa the applied part), then either its prescribed velocity
    (the force is a reaction) or central differences with local damping.
    Returns its contributions to (sum |F| free, sum |applied|, kinetic
    energy, work rate)."""
    ff = f[i, d] + fa
    f[i, d] = ff
    if fixed[i, d]:
        vv = vf * vpres[i, d]
        v[i, d] = vv
        u[i, d] += dt * vv
        return 0.0, abs(ff), 0.0, -ff * vv
    vo = v[i, d]
    damp = alpha * abs(ff)
    fd = ff
    if vo > 0.0:
        fd -= damp
    elif vo < 0.0:
        fd += damp
    m = mass[i]
    vv = vo + dt * fd / m
    v[i, d] = vv
    u[i, d] += dt * vv
    return abs(ff), abs(fa), 0.5 * m * vv * vv, fa * vv


@njit(**_INLINE)
def _record_step(step, hist, unbal, applied, ke, f, u, mon_nodes, mon_dir, mon_grp):
    """Row ``step`` of the history: unbalanced-force ratio, kinetic energy,
    per monitor group the reaction and the summed displacement.  Returns
    False if the step is not finite."""
    ngrp = (hist.shape[1] - 2) // 2
    if applied > 0.0:
        hist[step, 0] = unbal / applied
    else:
        hist[step, 0] = 0.0 if unbal == 0.0 else np.inf
    hist[step, 1] = ke
    for gi in range(ngrp):
        hist[step, 2 + 2 * gi] = 0.0
        hist[step, 3 + 2 * gi] = 0.0
    for k in range(mon_nodes.shape[0]):
        gi = mon_grp[k]
        nd = mon_nodes[k]
        d = mon_dir[k]
        hist[step, 2 + 2 * gi] -= f[nd, d]
        hist[step, 3 + 2 * gi] += u[nd, d]
    return math.isfinite(ke) and math.isfinite(hist[step, 0])


@njit(**_CACHE)
def run_chunk(zlaw, jlaw, gon, nsteps, dt, alpha, lf, vf0, dvf, grav,
              u, v, f, mass, mgrav, fixed, vpres, fext, x0,
              tets, dn, vol, wt, gptr, gnodes, gnptr, zp, zs, stress,
              j_nodes, j_cnt, j_w, j_axes, j_area, jp, js,
              b_nodes, b_cnt, b_w, b_axes, b_area, bp, bs,
              mon_nodes, mon_dir, mon_grp, hist, work, de, ev_, pending, a, evec):
    """Advances ``nsteps`` explicit steps (central differences with Cundall's
    local non-viscous damping, Itasca FLAC3D/3DEC):

        F = F_int + lf F_ext + m_g g
        v(t+dt/2) = v(t-dt/2) + dt/m (F - alpha |F| sgn(v(t-dt/2))),
        u(t+dt)   = u(t) + dt v(t+dt/2)                   (per component)

    Constrained components take their prescribed velocity times the velocity
    factor min(1, vf0 + (step + 1) dvf) (a linear ramp that starts loading
    without an inertial shock); the force they carry is their reaction.  Per step, ``hist`` receives
    [unbalanced-force ratio, kinetic energy, then per monitor group the
    reaction (sum of -F along its direction) and the mean displacement].
    The ratio is sum |F| over free components / sum of |applied| forces
    (external, gravity, and reactions of the constrained components).
    ``work[0]`` accumulates the work done on the model (``work[1]``: its
    largest value so far, step by step): reactions times the
    prescribed velocities and applied forces times the free velocities.
    Returns (status, steps done); status ST_NONFINITE stops at the first
    step whose kinetic energy is not finite."""
    nn = u.shape[0]
    for step in range(nsteps):
        vf = min(1.0, vf0 + (step + 1) * dvf)
        f[:, :] = 0.0
        if zlaw >= 0:
            zone_forces(zlaw, dt, v, f, x0, tets, dn, vol, wt, gptr, gnodes,
                        gnptr, zp, zs, stress, de, ev_, pending, a, evec)
        if j_area.shape[0] > 0:
            contact_forces(jlaw, dt, v, f, j_nodes, j_cnt, j_w, j_axes,
                           j_area, jp, js)
        if b_area.shape[0] > 0:
            contact_forces(literally(JOINT_BEARING), dt, v, f, b_nodes, b_cnt,
                           b_w, b_axes, b_area, bp, bs)
        unbal = 0.0
        applied = 0.0
        ke = 0.0
        wk = 0.0
        for i in range(nn):
            for d in range(3):
                load = lf * fext[i, d]
                if gon:     # gravity only when the scene declares it (literal: compiled away otherwise)
                    load += mgrav[i] * grav[d]
                a0, a1, a2, a3 = _advance_dof(i, d, load, f, v, u, mass, fixed, vpres, vf, alpha, dt)
                unbal += a0
                applied += a1
                ke += a2
                wk += a3
        work[0] += dt * wk
        if work[0] > work[1]:
            work[1] = work[0]
        if not _record_step(step, hist, unbal, applied, ke, f, u, mon_nodes, mon_dir, mon_grp):
            return ST_NONFINITE, step + 1
    return ST_OK, nsteps


@njit(**_CACHE)
def run_chunk_entry(zlaw, jlaw, gon, nsteps, dt, alpha, lf, vf0, dvf, grav,
                    u, v, f, mass, mgrav, fixed, vpres, fext, x0,
                    tets, dn, vol, wt, gptr, gnodes, gnptr, zp, zs, stress,
                    j_nodes, j_cnt, j_w, j_axes, j_area, jp, js,
                    b_nodes, b_cnt, b_w, b_axes, b_area, bp, bs,
                    mon_nodes, mon_dir, mon_grp, hist, work, de, ev_, pending, a, evec):
    """Entry point: specialises ``run_chunk`` on the literal law ids and
    gravity flag, so only the laws and effects a model uses are compiled
    (and cached)."""
    return run_chunk(literally(zlaw), literally(jlaw), literally(gon), nsteps, dt, alpha, lf,
                     vf0, dvf, grav, u, v, f, mass, mgrav, fixed, vpres, fext, x0,
                     tets, dn, vol, wt, gptr, gnodes, gnptr, zp, zs, stress,
                     j_nodes, j_cnt, j_w, j_axes, j_area, jp, js,
                     b_nodes, b_cnt, b_w, b_axes, b_area, bp, bs,
                     mon_nodes, mon_dir, mon_grp, hist, work, de, ev_, pending, a, evec)


# =============================================================================
# Rigid blocks: six degrees of freedom per block (physics.blocks: rigid)
# =============================================================================
@njit(**_INLINE)
def _rotate_by(R, wx, wy, wz):
    """R <- exp([w]x) R (Rodrigues' formula): a rotation by the vector w
    (rad) applied to the orientation R (3x3, body to global); the product
    stays orthonormal to rounding."""
    th = math.sqrt(wx * wx + wy * wy + wz * wz)
    if th == 0.0:
        return
    kx = wx / th
    ky = wy / th
    kz = wz / th
    c = math.cos(th)
    s = math.sin(th)
    C = 1.0 - c
    e00 = c + kx * kx * C
    e01 = kx * ky * C - kz * s
    e02 = kx * kz * C + ky * s
    e10 = ky * kx * C + kz * s
    e11 = c + ky * ky * C
    e12 = ky * kz * C - kx * s
    e20 = kz * kx * C - ky * s
    e21 = kz * ky * C + kx * s
    e22 = c + kz * kz * C
    for j in range(3):
        r0 = R[0, j]
        r1 = R[1, j]
        r2 = R[2, j]
        R[0, j] = e00 * r0 + e01 * r1 + e02 * r2
        R[1, j] = e10 * r0 + e11 * r1 + e12 * r2
        R[2, j] = e20 * r0 + e21 * r1 + e22 * r2


@njit(**_INLINE)
def _body_vec(R, b, x, y, z):
    """R[b] (x, y, z): a body-frame vector in global axes."""
    return (R[b, 0, 0] * x + R[b, 0, 1] * y + R[b, 0, 2] * z,
            R[b, 1, 0] * x + R[b, 1, 1] * y + R[b, 1, 2] * z,
            R[b, 2, 0] * x + R[b, 2, 1] * y + R[b, 2, 2] * z)


@njit(**_CACHE)
def run_chunk_rigid(jlaw, large, gon, nsteps, dt, alpha, lf, vf0, dvf, grav,
                    u, v, f, mass, mgrav, fixed, vpres,
                    R, om, mom, iinv, rfixed, ompres, rlen, fl,
                    pl_body, pl_lever, pl_force,
                    j_body, j_lever, j_axes, j_area, jp, js,
                    b_body, b_lever, b_axes, b_area, bp, bs,
                    mon_nodes, mon_dir, mon_grp, hist, work):
    """``run_chunk`` for rigid blocks.  Body i (a block, or a loading strip
    or support as a body whose motion is prescribed) has its reference
    point (the centroid) displaced by u[i], velocity v[i], orientation R[i]
    (body to global) and angular velocity om[i] (global axes).

    Sub-contact s joins bodies A = j_body[s, 0] and B = j_body[s, 1] at the
    point with body-frame levers j_lever[s, 0] and j_lever[s, 1] from their
    reference points.  Relative velocity at the point
    (v_B + om_B x r_B) - (v_A + om_A x r_A), r = R r0, in the local axes
    j_axes[s] = (n, t1, t2) (n from A to B): the initial axes for small
    displacements (``large`` = 0), the axes carried by block A's rotation
    for large ones.  The traction acts on A as +area t at r_A (force and
    moment r_A x F) and on B as -area t at r_B.  Gravity acts at the
    reference point (mgrav g); point loads pl_force (times lf) at their
    body-frame levers (their sum per body goes through ``fl``).  The
    unbalanced-force ratio counts moments divided by the body's lever
    scale rlen[i] (half its diagonal).

    Per component, central differences with local damping as in
    ``run_chunk``: translations with ``mass``, rotations with the inverse
    inertia iinv[i] (body frame; om_dot = R iinv R^T M, without the
    gyroscopic term om x I om: exact for rotation about a principal axis,
    and irrelevant to quasi-static runs).  Prescribed components
    (fixed/vpres; rotation components rfixed/ompres, an angular velocity
    in global axes) carry reactions: ``mom`` then holds the moment the
    prescribed rotation resists (its reaction is -mom).  ``hist`` and ``work`` as in ``run_chunk``."""
    nn = u.shape[0]
    for step in range(nsteps):
        vf = min(1.0, vf0 + (step + 1) * dvf)
        f[:, :] = 0.0
        fl[:, :] = 0.0
        mom[:, :] = 0.0
        for ci in range(2):
            body = j_body if ci == 0 else b_body
            lever = j_lever if ci == 0 else b_lever
            axes = j_axes if ci == 0 else b_axes
            area = j_area if ci == 0 else b_area
            par = jp if ci == 0 else bp
            st = js if ci == 0 else bs
            for s in range(area.shape[0]):
                a = body[s, 0]
                b = body[s, 1]
                rax, ray, raz = _body_vec(R, a, lever[s, 0, 0], lever[s, 0, 1], lever[s, 0, 2])
                rbx, rby, rbz = _body_vec(R, b, lever[s, 1, 0], lever[s, 1, 1], lever[s, 1, 2])
                rx = (v[b, 0] + om[b, 1] * rbz - om[b, 2] * rby) - (v[a, 0] + om[a, 1] * raz - om[a, 2] * ray)
                ry = (v[b, 1] + om[b, 2] * rbx - om[b, 0] * rbz) - (v[a, 1] + om[a, 2] * rax - om[a, 0] * raz)
                rz = (v[b, 2] + om[b, 0] * rby - om[b, 1] * rbx) - (v[a, 2] + om[a, 0] * ray - om[a, 1] * rax)
                if large:
                    nx, ny, nz = _body_vec(R, a, axes[s, 0], axes[s, 1], axes[s, 2])
                    ax, ay, az = _body_vec(R, a, axes[s, 3], axes[s, 4], axes[s, 5])
                    bx, by, bz = _body_vec(R, a, axes[s, 6], axes[s, 7], axes[s, 8])
                else:
                    nx, ny, nz = axes[s, 0], axes[s, 1], axes[s, 2]
                    ax, ay, az = axes[s, 3], axes[s, 4], axes[s, 5]
                    bx, by, bz = axes[s, 6], axes[s, 7], axes[s, 8]
                dun = dt * (rx * nx + ry * ny + rz * nz)
                du1 = dt * (rx * ax + ry * ay + rz * az)
                du2 = dt * (rx * bx + ry * by + rz * bz)
                if ci == 1:
                    joint_bearing(s, par, st, dun, du1, du2)
                elif jlaw == JOINT_ELASTIC:
                    joint_elastic(s, par, st, dun, du1, du2)
                elif jlaw == JOINT_BRITTLE_COULOMB:
                    joint_brittle_coulomb(s, par, st, dun, du1, du2)
                elif jlaw == JOINT_COUPLED:
                    joint_coupled(s, par, st, dun, du1, du2)
                elif jlaw == JOINT_FRICTION:
                    joint_friction(s, par, st, dun, du1, du2)
                ar = area[s]
                sn = st[s, JS_SN]
                s1 = st[s, JS_T1]
                s2 = st[s, JS_T2]
                fx = ar * (sn * nx + s1 * ax + s2 * bx)
                fy = ar * (sn * ny + s1 * ay + s2 * by)
                fz = ar * (sn * nz + s1 * az + s2 * bz)
                f[a, 0] += fx
                f[a, 1] += fy
                f[a, 2] += fz
                mom[a, 0] += ray * fz - raz * fy
                mom[a, 1] += raz * fx - rax * fz
                mom[a, 2] += rax * fy - ray * fx
                f[b, 0] -= fx
                f[b, 1] -= fy
                f[b, 2] -= fz
                mom[b, 0] -= rby * fz - rbz * fy
                mom[b, 1] -= rbz * fx - rbx * fz
                mom[b, 2] -= rbx * fy - rby * fx
        for k in range(pl_body.shape[0]):
            bd = pl_body[k]
            rx, ry, rz = _body_vec(R, bd, pl_lever[k, 0], pl_lever[k, 1], pl_lever[k, 2])
            fx = lf * pl_force[k, 0]
            fy = lf * pl_force[k, 1]
            fz = lf * pl_force[k, 2]
            fl[bd, 0] += fx
            fl[bd, 1] += fy
            fl[bd, 2] += fz
            mom[bd, 0] += ry * fz - rz * fy
            mom[bd, 1] += rz * fx - rx * fz
            mom[bd, 2] += rx * fy - ry * fx
        unbal = 0.0
        applied = 0.0
        ke = 0.0
        wk = 0.0
        for i in range(nn):
            for d in range(3):
                load = fl[i, d]
                if gon:
                    load += mgrav[i] * grav[d]
                a0, a1, a2, a3 = _advance_dof(i, d, load, f, v, u, mass, fixed, vpres, vf, alpha, dt)
                unbal += a0
                applied += a1
                ke += a2
                wk += a3
            # moments of the free components, damped; prescribed ones are
            # reactions (their moment is what the prescription resists)
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
            gx, gy, gz = _body_vec(R, i, ax_, ay_, az_)
            om[i, 0] = vf * ompres[i, 0] if rfixed[i, 0] else om[i, 0] + dt * gx
            om[i, 1] = vf * ompres[i, 1] if rfixed[i, 1] else om[i, 1] + dt * gy
            om[i, 2] = vf * ompres[i, 2] if rfixed[i, 2] else om[i, 2] + dt * gz
            # kinetic energy of rotation: 1/2 (R^T om) . I (R^T om), I diagonal in the body frame
            wx = R[i, 0, 0] * om[i, 0] + R[i, 1, 0] * om[i, 1] + R[i, 2, 0] * om[i, 2]
            wy = R[i, 0, 1] * om[i, 0] + R[i, 1, 1] * om[i, 1] + R[i, 2, 1] * om[i, 2]
            wz = R[i, 0, 2] * om[i, 0] + R[i, 1, 2] * om[i, 1] + R[i, 2, 2] * om[i, 2]
            ke += 0.5 * (wx * wx / iinv[i, 0, 0] + wy * wy / iinv[i, 1, 1] + wz * wz / iinv[i, 2, 2])
            _rotate_by(R[i], dt * om[i, 0], dt * om[i, 1], dt * om[i, 2])
        work[0] += dt * wk
        if work[0] > work[1]:
            work[1] = work[0]
        if not _record_step(step, hist, unbal, applied, ke, f, u, mon_nodes, mon_dir, mon_grp):
            return ST_NONFINITE, step + 1
    return ST_OK, nsteps


@njit(**_CACHE)
def run_chunk_rigid_entry(jlaw, large, gon, nsteps, dt, alpha, lf, vf0, dvf, grav,
                          u, v, f, mass, mgrav, fixed, vpres, R, om, mom, iinv, rfixed, ompres, rlen, fl,
                          pl_body, pl_lever, pl_force,
                          j_body, j_lever, j_axes, j_area, jp, js,
                          b_body, b_lever, b_axes, b_area, bp, bs,
                          mon_nodes, mon_dir, mon_grp, hist, work):
    """Entry point: specialises ``run_chunk_rigid`` on the literal joint law,
    displacement formulation and gravity flag."""
    return run_chunk_rigid(literally(jlaw), literally(large), literally(gon), nsteps, dt, alpha, lf, vf0, dvf, grav,
                           u, v, f, mass, mgrav, fixed, vpres, R, om, mom, iinv, rfixed, ompres, rlen, fl,
                           pl_body, pl_lever, pl_force,
                           j_body, j_lever, j_axes, j_area, jp, js,
                           b_body, b_lever, b_axes, b_area, bp, bs,
                           mon_nodes, mon_dir, mon_grp, hist, work)
