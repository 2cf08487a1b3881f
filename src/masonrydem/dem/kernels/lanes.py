"""The hot kernels across the lanes of a batch, eight lanes at a time
(kernels/layout.py: the lanes; step.py runs them for a batch of 8, 16, ...
lanes; a batch of one runs the kernels of one simulation, cells.py,
joints.py and step.py).

Eight lanes are one vector of AVX-512 (two of AVX2): every node value,
law parameter and state a kernel gathers by index is eight contiguous
doubles, held as an 8-tuple (``load8``) that stays in registers while a
sub-contact's nodes or a node's sub-contacts are summed, and that LLVM's
SLP vectoriser turns into vector instructions (kernels/__init__.py turns
it on).  Each lane's arithmetic is the kernels' of one simulation, term
by term in the same order, so a lane gives the bits of its run alone.
"""
import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core.extending import intrinsic

from .layout import JS_SN, JS_T1, JS_T2
from .joints import laws

_INLINE = dict(cache=True, inline="always", error_model="numpy")
# the three kernels a step calls once are functions of their own (LLVM may
# still inline them): numba inlines an inline="always" function by copying
# its typed code into every caller, which for these took half of a batch's
# compile (30 s -> 15 s; the steps as fast)
_CALL = dict(cache=True, error_model="numpy")
Z8 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


# offsets of the eight lanes, unsigned: an unsigned index is used as it
# is (a signed one is first checked for a negative value, each on its
# own), so the eight reads or writes are seen as one vector
_1, _2, _3, _4, _5, _6, _7 = (np.uintp(i) for i in range(1, 8))


@njit(**_INLINE)
def load8(a, o):
    """a[o:o + 8] of a 1-D array, as a tuple."""
    i = np.uintp(o)
    return a[i], a[i + _1], a[i + _2], a[i + _3], a[i + _4], a[i + _5], a[i + _6], a[i + _7]


@njit(**_INLINE)
def store8(a, o, t):
    """a[o:o + 8] = the tuple t."""
    i = np.uintp(o)
    a[i] = t[0]
    a[i + _1] = t[1]
    a[i + _2] = t[2]
    a[i + _3] = t[3]
    a[i + _4] = t[4]
    a[i + _5] = t[5]
    a[i + _6] = t[6]
    a[i + _7] = t[7]


@njit(**_INLINE)
def plus8(t, w, a, o):
    """t + w a[o:o + 8], lane by lane (t += w x)."""
    x = load8(a, o)
    return (t[0] + w * x[0], t[1] + w * x[1], t[2] + w * x[2], t[3] + w * x[3],
            t[4] + w * x[4], t[5] + w * x[5], t[6] + w * x[6], t[7] + w * x[7])


@njit(**_INLINE)
def minus8(t, w, a, o):
    """t - w a[o:o + 8], lane by lane (t -= w x)."""
    x = load8(a, o)
    return (t[0] - w * x[0], t[1] - w * x[1], t[2] - w * x[2], t[3] - w * x[3],
            t[4] - w * x[4], t[5] - w * x[5], t[6] - w * x[6], t[7] - w * x[7])


# --- cells -------------------------------------------------------------------
_V8 = ir.VectorType(ir.DoubleType(), 8)
_I32, _I64 = ir.IntType(32), ir.IntType(64)


@intrinsic
def cell8(typingctx, k, u, f, nodes, e, nl, o):
    """A cell's forces on its nodes in eight lanes, from lane o on:
    f[n_i] -= e (K^T U)_i, U the 24 displacements of its corners ``nodes``
    (an 8-tuple of 64-bit node indices) gathered from u, K its 24 x 24 matrix
    ``k`` (flat, C order), e its eight lanes' scales (an 8-tuple); u and f
    the nodes' values flat (node n component d lane b at (3 n + d) nl + b).
    Each value of K^T U is the fused multiply-adds of its 24 terms in
    order of j, from zero: what BLAS's kernels compute for one value of a
    product, so a lane gives the bits of its run alone, whose cells
    multiply by BLAS (cells.py); then each is scaled and subtracted, as a
    run alone does.  Written out for eight lanes at once: the 24 vectors
    of U loaded once, six outputs accumulated at a time, each k[j, i]
    broadcast.  On these small products BLAS's packing of the operands
    costs as much as its multiplications; this costs less than half."""
    if nodes.dtype.bitwidth != 64:          # the indices' arithmetic below is 64-bit
        return None
    sig = types.void(k, u, f, nodes, e, types.intp, types.intp)

    def codegen(context, builder, signature, args):
        kp, up, fp = (context.make_array(t)(context, builder, a).data for t, a in zip(signature.args[:3], args[:3]))
        nds, ev, nl, o = args[3:]
        fma = builder.module.globals.get("llvm.fma.v8f64") or ir.Function(
            builder.module, ir.FunctionType(_V8, [_V8, _V8, _V8]), "llvm.fma.v8f64")

        def vec(p, i):          # the eight lanes of the cell's value i (corner i // 3, component i % 3)
            nd = builder.extract_value(nds, i // 3)
            at = builder.add(builder.mul(builder.add(builder.mul(nd, ir.Constant(_I64, 3)), ir.Constant(_I64, i % 3)),
                                         nl), o)
            return builder.bitcast(builder.gep(p, [at]), _V8.as_pointer())

        undef, splat = ir.Constant(_V8, ir.Undefined), ir.Constant(ir.VectorType(_I32, 8), [0] * 8)
        scale = undef
        for b in range(8):
            scale = builder.insert_element(scale, builder.extract_value(ev, b), ir.Constant(_I32, b))
        U = [builder.load(vec(up, j), align=8) for j in range(24)]
        for i0 in range(0, 24, 6):
            acc = [ir.Constant(_V8, [0.0] * 8)] * 6
            for j in range(24):
                for r in range(6):
                    kji = builder.load(builder.gep(kp, [ir.Constant(_I64, 24 * j + i0 + r)]))
                    kv = builder.shuffle_vector(builder.insert_element(undef, kji, ir.Constant(_I32, 0)), undef, splat)
                    acc[r] = builder.call(fma, [kv, U[j], acc[r]])
            for r in range(6):
                p = vec(fp, i0 + r)
                builder.store(builder.fsub(builder.load(p, align=8), builder.fmul(scale, acc[r])), p, align=8)
        return context.get_dummy_value()
    return sig, codegen


@njit(**_CALL)
def cell_forces(nodes, cells, nl):
    """cells.cell_forces across the lanes: each cell in order, eight lanes
    at a time (``cell8``), so that each node sums its cells' forces in the
    order a run alone does.  Lane b of a cell's K^T U is the row of U K
    that a run alone computes, the same terms in the same order (K is
    symmetric only to round-off, so the transpose, not K)."""
    uf, ff = nodes.u.ravel(), nodes.f.ravel()
    ix, kind, K = cells.nodes, cells.kind, cells.K
    scale = cells.scale.ravel()
    for c in range(ix.shape[0]):
        corners = (ix[c, 0], ix[c, 1], ix[c, 2], ix[c, 3], ix[c, 4], ix[c, 5], ix[c, 6], ix[c, 7])
        Kc = K[kind[c]].ravel()
        for o in range(0, nl, 8):
            cell8(Kc, uf, ff, corners, load8(scale, c * nl + o), nl, o)


# --- sub-contacts ----------------------------------------------------------------
@njit(**_INLINE)
def _dot(dt, x, y, z, nx, ny, nz):
    return dt * (x * nx + y * ny + z * nz)


@njit(**_INLINE)
def _increments(dt, o, x, y, z, nx, ny, nz):
    """joints.local_increments' component along (nx, ny, nz), lane by lane:
    dt (x nx + y ny + z nz), dt[o + b] lane b's step."""
    return (_dot(dt[o], x[0], y[0], z[0], nx, ny, nz), _dot(dt[o + 1], x[1], y[1], z[1], nx, ny, nz),
            _dot(dt[o + 2], x[2], y[2], z[2], nx, ny, nz), _dot(dt[o + 3], x[3], y[3], z[3], nx, ny, nz),
            _dot(dt[o + 4], x[4], y[4], z[4], nx, ny, nz), _dot(dt[o + 5], x[5], y[5], z[5], nx, ny, nz),
            _dot(dt[o + 6], x[6], y[6], z[6], nx, ny, nz), _dot(dt[o + 7], x[7], y[7], z[7], nx, ny, nz))


@njit(**_INLINE)
def _traction(ar, s0, s1, s2, nx, ax, bx):
    return ar * (s0 * nx + s1 * ax + s2 * bx)


@njit(**_INLINE)
def _tractions(ar, sn, t1, t2, nx, ax, bx):
    """joints.traction_force's component along one axis, lane by lane."""
    return (_traction(ar, sn[0], t1[0], t2[0], nx, ax, bx), _traction(ar, sn[1], t1[1], t2[1], nx, ax, bx),
            _traction(ar, sn[2], t1[2], t2[2], nx, ax, bx), _traction(ar, sn[3], t1[3], t2[3], nx, ax, bx),
            _traction(ar, sn[4], t1[4], t2[4], nx, ax, bx), _traction(ar, sn[5], t1[5], t2[5], nx, ax, bx),
            _traction(ar, sn[6], t1[6], t2[6], nx, ax, bx), _traction(ar, sn[7], t1[7], t2[7], nx, ax, bx))


@njit(**_CALL)
def contact_forces(jlaw, dt, nodes, sc, nl):
    """joints._deformable_contacts across the lanes (``dt``: each lane's
    step): (1) each sub-contact gathers its relative velocity, eight lanes
    of a node a vector, and stores its displacement increments (row
    s S + b of the work space); (2) the law on every sub-contact and lane;
    (3) each stores its force; (4) each node gathers the forces of its
    sub-contacts, in sub-contact order."""
    wt = sc.force.T             # Fortran-ordered (rows x 3): its transpose's rows are the columns, contiguous
    w0, w1, w2 = wt[0], wt[1], wt[2]
    increments(dt, nodes.v.ravel(), sc, w0, w1, w2, nl)
    laws(jlaw, w0, w1, w2, sc.par, sc.state)
    forces(sc, w0, w1, w2, nl)
    gather_forces(nodes.f.ravel(), sc.gptr, sc.gs, sc.gw, w0, w1, w2, nl)


@njit(**_INLINE)
def increments(dt, vf, sc, w0, w1, w2, nl):
    """(1) of ``contact_forces``: vf the nodes' velocities flat (node i
    component d lane b at (3 i + d) S + b)."""
    w, ix, axes, cnt = sc.w, sc.nodes, sc.axes, sc.cnt
    for s in range(sc.area.shape[0]):
        nx, ny, nz, ax, ay, az = axes[s, 0], axes[s, 1], axes[s, 2], axes[s, 3], axes[s, 4], axes[s, 5]
        bx, by, bz = axes[s, 6], axes[s, 7], axes[s, 8]
        for o in range(0, nl, 8):
            rx, ry, rz = Z8, Z8, Z8
            for k in range(cnt[s, 0]):
                at = 3 * nl * ix[s, k] + o
                wk = w[s, k]
                rx, ry, rz = minus8(rx, wk, vf, at), minus8(ry, wk, vf, at + nl), minus8(rz, wk, vf, at + 2 * nl)
            for k in range(4, 4 + cnt[s, 1]):
                at = 3 * nl * ix[s, k] + o
                wk = w[s, k]
                rx, ry, rz = plus8(rx, wk, vf, at), plus8(ry, wk, vf, at + nl), plus8(rz, wk, vf, at + 2 * nl)
            r0 = s * nl + o
            store8(w0, r0, _increments(dt, o, rx, ry, rz, nx, ny, nz))
            store8(w1, r0, _increments(dt, o, rx, ry, rz, ax, ay, az))
            store8(w2, r0, _increments(dt, o, rx, ry, rz, bx, by, bz))


@njit(**_INLINE)
def forces(sc, w0, w1, w2, nl):
    """(3) of ``contact_forces``: each sub-contact's force on side A."""
    axes, area = sc.axes, sc.area
    st = sc.state.T
    sn_, t1_, t2_ = st[JS_SN], st[JS_T1], st[JS_T2]
    for s in range(area.shape[0]):
        ar = area[s]
        nx, ny, nz, ax, ay, az = axes[s, 0], axes[s, 1], axes[s, 2], axes[s, 3], axes[s, 4], axes[s, 5]
        bx, by, bz = axes[s, 6], axes[s, 7], axes[s, 8]
        for o in range(0, nl, 8):
            r0 = s * nl + o
            sn, t1, t2 = load8(sn_, r0), load8(t1_, r0), load8(t2_, r0)
            store8(w0, r0, _tractions(ar, sn, t1, t2, nx, ax, bx))
            store8(w1, r0, _tractions(ar, sn, t1, t2, ny, ay, by))
            store8(w2, r0, _tractions(ar, sn, t1, t2, nz, az, bz))


@njit(**_INLINE)
def gather_forces(ff, gptr, gs, gw, w0, w1, w2, nl):
    """joints.gather_forces across the lanes: f[i] += sum_j gw[j]
    force[gs[j]], in that order, a node's eight lanes a vector held while
    its sub-contacts are summed (ff: the nodes' forces flat, node i
    component d lane b at (3 i + d) S + b; w0, w1, w2: the forces'
    components, row s S + b)."""
    for i in range(gptr.shape[0] - 1):
        j0 = gptr[i]
        j1 = gptr[i + 1]
        if j0 == j1:
            continue
        for o in range(0, nl, 8):
            at = 3 * nl * i + o
            fx, fy, fz = load8(ff, at), load8(ff, at + nl), load8(ff, at + 2 * nl)
            for j in range(j0, j1):
                r0 = gs[j] * nl + o
                wj = gw[j]
                fx, fy, fz = plus8(fx, wj, w0, r0), plus8(fy, wj, w1, r0), plus8(fz, wj, w2, r0)
            store8(ff, at, fx)
            store8(ff, at + nl, fy)
            store8(ff, at + 2 * nl, fz)


# --- the nodes ---------------------------------------------------------------------
@njit(**_INLINE)
def _load(lf, fext, mg, g, gon):
    """The applied load of a component: lf fext (+ its weight)."""
    load = lf * fext
    if gon:
        load += mg * g
    return load


@njit(**_INLINE)
def _load8(lf, fext, mgrav, at, mo, o, g, gon):
    """The applied loads of a component in eight lanes, from lane o on
    (``at`` and ``mo``: its first lane's place in fext and in mgrav)."""
    return (_load(lf[o], fext[at], mgrav[mo], g, gon), _load(lf[o + 1], fext[at + 1], mgrav[mo + 1], g, gon),
            _load(lf[o + 2], fext[at + 2], mgrav[mo + 2], g, gon), _load(lf[o + 3], fext[at + 3], mgrav[mo + 3], g, gon),
            _load(lf[o + 4], fext[at + 4], mgrav[mo + 4], g, gon), _load(lf[o + 5], fext[at + 5], mgrav[mo + 5], g, gon),
            _load(lf[o + 6], fext[at + 6], mgrav[mo + 6], g, gon), _load(lf[o + 7], fext[at + 7], mgrav[mo + 7], g, gon))


@njit(**_INLINE)
def _velocity(ff, vo, m, vp, vf, alpha, dt, fixed):
    """The component's new velocity (advance.advance_nodes)."""
    fd = ff - alpha * abs(ff) * ((vo > 0.0) - (vo < 0.0))
    return vf * vp if fixed else vo + dt * fd / m


@njit(**_CALL)
def advance_nodes(gon, grav, vf, ctl, nodes, sums, nl):
    """advance.advance_nodes across the lanes, eight at a time: the forces,
    velocities and displacements of every component, then per lane the
    four sums in the order of the components, held in registers (sums
    (4, S): sum |F| free, sum |applied|, kinetic energy, work rate)."""
    n = nodes.u.shape[0] * 3
    u, v, f = nodes.u.ravel(), nodes.v.ravel(), nodes.f.ravel()
    mass, vpres, fext, mgrav = nodes.mass.ravel(), nodes.vpres.ravel(), nodes.fext.ravel(), nodes.mgrav.ravel()
    fixed = nodes.fixed.ravel()
    dt, lf, alpha = ctl.dt, ctl.lf, ctl.alpha
    for o in range(0, nl, 8):
        for k in range(n):
            fk = fixed[k]
            at = k * nl + o
            mo = (k // 3) * nl + o
            g = grav[k % 3]
            load = _load8(lf, fext, mgrav, at, mo, o, g, gon)
            f0 = load8(f, at)
            ff = (f0[0] + load[0], f0[1] + load[1], f0[2] + load[2], f0[3] + load[3], f0[4] + load[4],
                  f0[5] + load[5], f0[6] + load[6], f0[7] + load[7])
            store8(f, at, ff)
            vv = (_velocity(ff[0], v[at], mass[at], vpres[at], vf[o], alpha[o], dt[o], fk),
                  _velocity(ff[1], v[at + 1], mass[at + 1], vpres[at + 1], vf[o + 1], alpha[o + 1], dt[o + 1], fk),
                  _velocity(ff[2], v[at + 2], mass[at + 2], vpres[at + 2], vf[o + 2], alpha[o + 2], dt[o + 2], fk),
                  _velocity(ff[3], v[at + 3], mass[at + 3], vpres[at + 3], vf[o + 3], alpha[o + 3], dt[o + 3], fk),
                  _velocity(ff[4], v[at + 4], mass[at + 4], vpres[at + 4], vf[o + 4], alpha[o + 4], dt[o + 4], fk),
                  _velocity(ff[5], v[at + 5], mass[at + 5], vpres[at + 5], vf[o + 5], alpha[o + 5], dt[o + 5], fk),
                  _velocity(ff[6], v[at + 6], mass[at + 6], vpres[at + 6], vf[o + 6], alpha[o + 6], dt[o + 6], fk),
                  _velocity(ff[7], v[at + 7], mass[at + 7], vpres[at + 7], vf[o + 7], alpha[o + 7], dt[o + 7], fk))
            store8(v, at, vv)
            u0 = load8(u, at)
            store8(u, at, (u0[0] + dt[o] * vv[0], u0[1] + dt[o + 1] * vv[1], u0[2] + dt[o + 2] * vv[2],
                           u0[3] + dt[o + 3] * vv[3], u0[4] + dt[o + 4] * vv[4], u0[5] + dt[o + 5] * vv[5],
                           u0[6] + dt[o + 6] * vv[6], u0[7] + dt[o + 7] * vv[7]))
        unbal, applied, ke, wk = Z8, Z8, Z8, Z8
        for k in range(n):
            at = k * nl + o
            mo = (k // 3) * nl + o
            g = grav[k % 3]
            ff, vv = load8(f, at), load8(v, at)
            if fixed[k]:
                applied = (applied[0] + abs(ff[0]), applied[1] + abs(ff[1]), applied[2] + abs(ff[2]),
                           applied[3] + abs(ff[3]), applied[4] + abs(ff[4]), applied[5] + abs(ff[5]),
                           applied[6] + abs(ff[6]), applied[7] + abs(ff[7]))
                wk = (wk[0] + -ff[0] * vv[0], wk[1] + -ff[1] * vv[1], wk[2] + -ff[2] * vv[2],
                      wk[3] + -ff[3] * vv[3], wk[4] + -ff[4] * vv[4], wk[5] + -ff[5] * vv[5],
                      wk[6] + -ff[6] * vv[6], wk[7] + -ff[7] * vv[7])
            else:
                load = _load8(lf, fext, mgrav, at, mo, o, g, gon)
                m = load8(mass, at)
                unbal = (unbal[0] + abs(ff[0]), unbal[1] + abs(ff[1]), unbal[2] + abs(ff[2]), unbal[3] + abs(ff[3]),
                         unbal[4] + abs(ff[4]), unbal[5] + abs(ff[5]), unbal[6] + abs(ff[6]), unbal[7] + abs(ff[7]))
                applied = (applied[0] + abs(load[0]), applied[1] + abs(load[1]), applied[2] + abs(load[2]),
                           applied[3] + abs(load[3]), applied[4] + abs(load[4]), applied[5] + abs(load[5]),
                           applied[6] + abs(load[6]), applied[7] + abs(load[7]))
                ke = (ke[0] + 0.5 * m[0] * vv[0] * vv[0], ke[1] + 0.5 * m[1] * vv[1] * vv[1],
                      ke[2] + 0.5 * m[2] * vv[2] * vv[2], ke[3] + 0.5 * m[3] * vv[3] * vv[3],
                      ke[4] + 0.5 * m[4] * vv[4] * vv[4], ke[5] + 0.5 * m[5] * vv[5] * vv[5],
                      ke[6] + 0.5 * m[6] * vv[6] * vv[6], ke[7] + 0.5 * m[7] * vv[7] * vv[7])
                wk = (wk[0] + load[0] * vv[0], wk[1] + load[1] * vv[1], wk[2] + load[2] * vv[2],
                      wk[3] + load[3] * vv[3], wk[4] + load[4] * vv[4], wk[5] + load[5] * vv[5],
                      wk[6] + load[6] * vv[6], wk[7] + load[7] * vv[7])
        store8(sums[0], o, unbal)
        store8(sums[1], o, applied)
        store8(sums[2], o, ke)
        store8(sums[3], o, wk)
