"""Block material (zone) laws and the zone forces.

Every zone first takes the elastic trial (``zone_elastic``); a plastic law
then corrects stress[t] in place and updates its state zs[t].
"""
import math

from numba import njit
from numba.extending import overload

from .layout import ZONE_ELASTIC, ZONE_MOHR_COULOMB, ZONE_NONE, ZP_C, ZP_FT, ZP_G, ZP_GF, ZP_K, ZP_NPHI, ZS_EPT, ZS_EULT, ZS_H
from .linalg import eig_sym3
from .static import choose

_INLINE = dict(cache=True, inline="always", error_model="numpy")
# a zone law's kernel is a function of its own, compiled (and cached) once
# and shared by every step kernel that uses the law (joints.py)
_CALL = dict(cache=True, error_model="numpy")


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


def _zone_forces(plastic):
    """The zone kernel of an elastic (``plastic`` False) or elasto-plastic
    zone law: ``plastic`` is a constant of the compiled function, so an
    elastic model carries no yield check at all."""
    @njit(**_CALL)
    def zone_forces_(dt, nodes, zones, scratch):
        """Adds the zones' nodal forces to ``nodes.f``.

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
        v, f, x0 = nodes.v, nodes.f, nodes.x0
        tets, dn, vol, wt = zones.tets, zones.dn, zones.vol, zones.wt
        gptr, gnodes, gnptr = zones.gptr, zones.gnodes, zones.gnptr
        zp, zs, stress = zones.par, zones.state, zones.stress
        de, ev_, pending, a, evec = scratch.de, scratch.ev, scratch.pending, scratch.a, scratch.evec
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
                if plastic:
                    if not mohr_coulomb_elastic(t, zp, zs, stress):
                        pending[npend, 0] = t
                        pending[npend, 1] = g
                        npend += 1
                _tet_forces(t, wt[t] * vol[t], stress[t, 0], stress[t, 1], stress[t, 2],
                            stress[t, 3], stress[t, 4], stress[t, 5], tets, dn, f)
        if plastic:     # the return mapping of the zones queued as possibly yielding
            for i in range(npend):
                t = pending[i, 0]
                g = pending[i, 1]
                trial = de[0]           # free in this pass: the trial stress
                trial[:] = stress[t]
                if zone_mohr_coulomb(t, zp, zs, stress, a, evec, x0, gnodes, gnptr[g], gnptr[g + 1]):
                    _tet_forces(t, wt[t] * vol[t], stress[t, 0] - trial[0], stress[t, 1] - trial[1],
                                stress[t, 2] - trial[2], stress[t, 3] - trial[3], stress[t, 4] - trial[4],
                                stress[t, 5] - trial[5], tets, dn, f)

    return zone_forces_


@njit(**_INLINE)
def _no_zones(dt, nodes, zones, scratch):
    """Rigid blocks: no zones."""


_ZONE_FORCES = {ZONE_NONE: _no_zones, ZONE_ELASTIC: _zone_forces(False), ZONE_MOHR_COULOMB: _zone_forces(True)}


def zone_forces(zlaw, dt, nodes, zones, scratch):
    """Adds the zones' nodal forces to ``nodes.f`` under the zone law
    ``zlaw`` (a literal id, chosen when the caller compiles: static.py)."""
    raise TypeError("zone_forces: only callable from compiled code")


@overload(zone_forces, prefer_literal=True)
def _zone_forces_of(zlaw, dt, nodes, zones, scratch):
    impl = choose(_ZONE_FORCES, zlaw, "the zone law")
    return lambda zlaw, dt, nodes, zones, scratch: impl(dt, nodes, zones, scratch)
