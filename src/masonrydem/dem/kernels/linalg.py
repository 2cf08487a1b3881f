"""Small linear algebra of the kernels: the eigen-decomposition of a
symmetric 3x3 tensor and the rotations of rigid bodies."""
import math

from numba import njit

_INLINE = dict(cache=True, inline="always", error_model="numpy")


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


@njit(**_INLINE)
def rotate_by(R, wx, wy, wz):
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
def body_vec(R, b, x, y, z):
    """R[b] (x, y, z): a body-frame vector in global axes."""
    return (R[b, 0, 0] * x + R[b, 0, 1] * y + R[b, 0, 2] * z,
            R[b, 1, 0] * x + R[b, 1, 1] * y + R[b, 1, 2] * z,
            R[b, 2, 0] * x + R[b, 2, 1] * y + R[b, 2, 2] * z)


@njit(**_INLINE)
def add_force(f, mom, b, rx, ry, rz, fx, fy, fz):
    """Body b takes the force F = (fx, fy, fz) at the lever r = (rx, ry, rz)
    from its reference point: f[b] += F, mom[b] += r x F."""
    f[b, 0] += fx
    f[b, 1] += fy
    f[b, 2] += fz
    mom[b, 0] += ry * fz - rz * fy
    mom[b, 1] += rz * fx - rx * fz
    mom[b, 2] += rx * fy - ry * fx
