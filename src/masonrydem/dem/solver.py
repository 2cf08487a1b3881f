"""Explicit time integration of an assembled model as an (init, advance)
pair over a state (in the manner of JAX-MD's simulate.py):

    state = init(assembly, Numerics(damping=0.4, safety=0.9))
    state, history = advance(state, Controls(), n)

Quasi-static mode: a unit pseudo step and scaled masses (density scaling
from the Gershgorin bounds of the stiffness, stability.py), local damping;
dynamic mode: physical masses.  docs/formulation.md, section 8, gives the
equations.

The arrays live in a Batch: the kernels' containers with a lane per
simulation of one mesh (kernels/layout.py), advanced in place by the step
kernel (kernels.step).  A State is one lane's simulation: its arrays are
views of its lane, and its step count, velocity factor and energy are a
new value at every advance.  ``init`` makes a batch of one; lockstep.py
advances the lanes of a larger batch together.  stops.py runs an advance
loop under stop rules.
"""
import math
from typing import NamedTuple

import numpy as np

from . import kernels as K
from ..errors import InputError
from .history import from_kernel
from .kernels.step import specialised
from .stability import DYNAMIC, QUASI_STATIC, critical_step, physical_masses, scaled_masses, time_step


class Numerics(NamedTuple):
    """How to integrate: ``mode`` quasi-static (dt = 1, scaled masses) or
    dynamic (physical masses, dt given or ``safety`` times the critical
    step); local ``damping``, which quasi-static integration needs given
    and dynamic integration takes as none unless given; the ``safety``
    factor on the critical step, always given (a scene's numerics.damping
    and numerics.safety: the scene schema holds their one default);
    deformable blocks stop a run beyond ``rotation_limit`` radians (small
    displacements)."""
    mode: str = QUASI_STATIC
    damping: float = None
    safety: float = None
    dt: float = None
    rotation_limit: float = 0.05


class Integrator(NamedTuple):
    """What init fixes: the step, the damping, omega_max dt / 2 of the
    undamped system (``c``, the divergence guard), the smallest zone, cell
    or body size, the rotation limit and the step kernel compiled for the
    model's laws and effects."""
    mode: str
    dt: float
    dt_crit: float
    alpha: float
    c: float
    h_min: float
    rotation_limit: float
    gravity_on: int
    kernel: object


class State(NamedTuple):
    """One simulation: its lane of a Batch, whose arrays its properties
    view (nodes: u, v, f, masses, prescribed velocities; zones; joints;
    bearings; rigid bodies; the work done on the model since the start
    and its largest value), the step count, the velocity factor of the
    prescribed velocities, the initial kinetic energy (set at the first
    advance) and whether the last step was finite."""
    assembly: object
    integrator: Integrator
    batch: object
    lane: int
    step: int = 0
    velocity_factor: float = 1.0
    energy_in: float = None
    finite: bool = True

    @property
    def nodes(self):
        return self.batch.view("nodes", self.lane)

    @property
    def zones(self):
        return self.batch.view("zones", self.lane)

    @property
    def joints(self):
        return self.batch.view("joints", self.lane)

    @property
    def bearings(self):
        return self.batch.view("bearings", self.lane)

    @property
    def bodies(self):
        return self.batch.view("bodies", self.lane)

    @property
    def work(self):
        return self.batch.work[:, self.lane]


class Controls(NamedTuple):
    """Of one stage: the prescribed velocities grow linearly from zero to
    their full value over its first ``ramp_steps`` steps (``begin``); the
    applied forces are scaled by ``load_factor``."""
    ramp_steps: int = 0
    load_factor: float = 1.0


def init(assembly, numerics):
    """The state of ``assembly`` at rest, with its masses and step: the one
    lane of a batch of one."""
    return Batch(assembly, numerics, 1).load(0, assembly)


def _checked(numerics):
    """(mode, damping, safety) of ``numerics``, refused where invalid."""
    mode, safety, damping = numerics.mode, numerics.safety, numerics.damping
    if mode not in (QUASI_STATIC, DYNAMIC):
        raise InputError("solver.mode", f"must be {QUASI_STATIC!r} or {DYNAMIC!r}, got {mode!r}")
    if not (isinstance(safety, (int, float)) and 0 < safety <= 1):
        raise InputError("solver.safety", f"must be in (0, 1], got {safety!r}")
    if damping is None and mode == QUASI_STATIC:
        raise InputError("solver.damping", "quasi-static integration needs its local damping given "
                                           "(a scene's numerics.damping)")
    damping = 0.0 if damping is None else damping
    if not (0.0 <= damping < 1.0):
        raise InputError("solver.damping", f"must be in [0, 1), got {damping!r}")
    return mode, float(damping), safety


def _lane_arrays(assembly, numerics):
    """A run's own arrays at rest (by container and field, as the
    assembly's, without a lane axis) and its Integrator."""
    a = assembly
    mode, alpha, safety = _checked(numerics)
    free = a.nodes.fixed.min(axis=1) == 0
    knode = a.stiffness.max(axis=1)
    floating = np.flatnonzero(free & (knode <= 0))
    if floating.size:
        raise InputError("model", f"{floating.size} free nodes carry no stiffness (first: node {floating[0]})")
    # a component that no element stiffens takes its node's bound
    k = np.where(a.stiffness > 0, a.stiffness, knode[:, None])
    mass, crit = _inertia(mode, k, np.repeat(a.nodes.mgrav[:, None], 3, axis=1), free, alpha, safety)
    n = a.n
    z3 = np.zeros((n, 3))
    own = dict(nodes=dict(u=z3, v=z3, f=z3, mass=mass, mgrav=a.nodes.mgrav, vpres=a.nodes.vpres, fext=a.nodes.fext),
               zones=dict(par=a.zones.par, state=np.zeros_like(a.zones.state), stress=np.zeros_like(a.zones.stress)),
               cells=dict(scale=a.cells.scale),
               joints=dict(par=a.joints.par, state=a.joints.state, force=np.zeros_like(a.joints.force)),
               bearings=dict(par=a.bearings.par, state=a.bearings.state, force=np.zeros_like(a.bearings.force)),
               bodies=dict(R=a.bodies.R, om=a.bodies.om, mom=a.bodies.mom, iinv=a.bodies.iinv, ompres=a.bodies.ompres,
                           fl=a.bodies.fl, load_force=a.bodies.load_force))
    if a.rigid:
        iinv, crit_r = _rotations(a, mode, alpha, safety)
        crit += crit_r
        own["bodies"].update(om=z3, mom=z3, iinv=iinv, fl=z3)
    dt, dt_crit = time_step(mode, crit, safety, numerics.dt)
    integ = Integrator(mode=mode, dt=dt, dt_crit=dt_crit, alpha=alpha,
                       c=min(dt / dt_crit / math.sqrt(1.0 + alpha), 0.999), h_min=a.h_min,
                       rotation_limit=math.inf if a.large else float(numerics.rotation_limit),
                       gravity_on=int(np.any(a.gravity != 0.0)), kernel=None)
    return own, integ


# container -> (its name in the Assembly, the kernels' class)
_CONTAINERS = dict(nodes=("nodes", K.Nodes), zones=("zones", K.Zones), cells=("cells", K.Cells),
                   joints=("joints", K.Contacts), bearings=("bearings", K.Contacts), bodies=("bodies", K.Bodies))


class Batch:
    """S simulations of one mesh, a lane each, advanced in lock-step by the
    step kernel: the kernels' containers with a lane axis on each run's
    own arrays (kernels/layout.py, PER_LANE), the mesh's arrays once.
    ``load`` puts a run at rest into a lane, ``clear`` empties one (all
    zero: it computes zeros, cheaply, until loaded again).  Every lane's
    model must share the first's mesh, topology, constraints, laws and
    numerics (``fits``)."""

    def __init__(self, assembly, numerics, lanes):
        self.assembly, self.numerics, self.lanes = assembly, numerics, int(lanes)
        self.key = lane_key(assembly, numerics)
        S = self.lanes
        self.containers = {}
        for name, (attr, cls) in _CONTAINERS.items():
            c = getattr(assembly, attr)
            fields = {}
            for f in cls._fields:
                x = getattr(c, f)
                if f not in K.PER_LANE[cls.__name__]:
                    fields[f] = x
                elif cls is K.Contacts:
                    fields[f] = np.zeros((x.shape[0] * S, x.shape[1]), order="F")
                else:
                    fields[f] = np.zeros(x.shape + (S,))
            self.containers[name] = cls(**fields)
        a = assembly
        nt, nc, nk = a.zones.tets.shape[0], a.cells.nodes.shape[0], a.cells.K.shape[0]
        gsize = np.diff(a.zones.gptr).max() if nt else 1
        self.scratch = K.Scratch(np.zeros((gsize, 6)), np.zeros(gsize), np.zeros((max(nt, 1), 2), np.int64),
                                 np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((24, nc * S)), np.zeros((nk, 24, nc * S)),
                                 np.zeros((4, S)), np.zeros(S))
        self.work = np.zeros((2, S))
        self.ctl = K.Controls(np.zeros(S, np.int64), np.zeros(S, np.int64), np.ones(S), np.ones(S), np.ones(S),
                              np.zeros(S), _checked(numerics)[1], a.gravity)
        self.kernel = None

    def fits(self, assembly, numerics):
        """Whether ``assembly`` under ``numerics`` can take a lane."""
        return lane_key(assembly, numerics) == self.key

    def view(self, name, lane):
        """Lane ``lane``'s view of the container ``name`` (a run's arrays)."""
        c = self.containers[name]
        per = K.PER_LANE[type(c).__name__]
        if type(c) is K.Contacts:
            return c._replace(**{f: getattr(c, f)[lane::self.lanes] for f in per})
        return c._replace(**{f: getattr(c, f)[..., lane] for f in per})

    def load(self, lane, assembly):
        """The State of ``assembly`` at rest in lane ``lane``."""
        if assembly is not self.assembly and not self.fits(assembly, self.numerics):
            raise ValueError("a batch's lanes share one mesh and its numerics: this model differs")
        own, integ = _lane_arrays(assembly, self.numerics)
        for name, fields in own.items():
            view = self.view(name, lane)
            for f, x in fields.items():
                getattr(view, f)[...] = x
        self.work[:, lane] = 0.0
        if self.kernel is None:
            self.ctl.dt[:] = integ.dt
            self.kernel = specialised(self.args(0))
        return State(assembly, integ._replace(kernel=self.kernel), self, lane)

    def clear(self, lane):
        """Lane ``lane`` emptied: every array of its own zero."""
        for name in self.containers:
            view = self.view(name, lane)
            for f in K.PER_LANE[type(view).__name__]:
                getattr(view, f)[...] = 0.0
        self.work[:, lane] = 0.0
        self.ctl.lf[lane] = self.ctl.dvf[lane] = self.ctl.vf0[lane] = 0.0

    def narrowed(self, lanes):
        """A batch of the lanes ``lanes`` of this one (their arrays and
        controls copied, in that order), sharing its kernel: a batch whose
        last runs leave lanes empty narrows, since an empty lane costs as
        much as a busy one."""
        new = Batch.__new__(Batch)
        new.__dict__.update(self.__dict__)
        new.lanes, idx = len(lanes), np.asarray(lanes)
        new.containers = {}
        for name, c in self.containers.items():
            per = K.PER_LANE[type(c).__name__]
            if type(c) is K.Contacts:
                n = c.area.shape[0]
                rows = (np.arange(n)[:, None] * self.lanes + idx[None, :]).ravel()
                new.containers[name] = c._replace(**{f: np.asfortranarray(getattr(c, f)[rows]) for f in per})
            else:
                new.containers[name] = c._replace(**{f: np.ascontiguousarray(getattr(c, f)[..., idx]) for f in per})
        S, sc = new.lanes, self.scratch
        new.scratch = sc._replace(U=np.zeros((24, sc.U.shape[1] // self.lanes * S)),
                                  F=np.zeros((sc.F.shape[0], 24, sc.F.shape[2] // self.lanes * S)),
                                  sums=np.zeros((4, S)), vf=np.zeros(S))
        new.work = np.ascontiguousarray(self.work[:, idx])
        c = self.ctl
        new.ctl = c._replace(**{f: np.ascontiguousarray(getattr(c, f)[idx])
                                for f in ("step0", "k0", "dt", "lf", "vf0", "dvf")})
        return new

    def args(self, n, hist=None):
        """The step kernel's arguments for ``n`` steps."""
        a, c = self.assembly, self.containers
        if hist is None:
            hist = np.empty((n, K.h_width(len(a.monitor_names)), self.lanes))
        return (a.zlaw, a.jlaw, int(a.rigid), int(a.large), int(np.any(a.gravity != 0.0)), n, self.ctl, c["nodes"],
                c["zones"], c["cells"], c["joints"], c["bearings"], c["bodies"], a.monitors, hist, self.work,
                self.scratch)

    def set_lane(self, state, controls, k0=0):
        """The kernel's controls of ``state``'s lane for a chunk under
        ``controls``, ``k0`` of its steps done."""
        b, ctl = state.lane, self.ctl
        ctl.step0[b], ctl.k0[b], ctl.dt[b] = state.step, k0, state.integrator.dt
        ctl.lf[b], ctl.vf0[b], ctl.dvf[b] = float(controls.load_factor), float(state.velocity_factor), _ramp(controls)

    def advance(self, n):
        """Every lane ``n`` steps (fewer if a step of a lane is not
        finite): (kernel status, steps done, the history rows (done,
        columns, S))."""
        args = self.args(n)
        code, done = self.kernel(*args)
        return code, done, args[14][:done]


def lane_key(assembly, numerics):
    """What the lanes of a batch share: the mesh, topology, constraints,
    monitors and laws of the model, and the numerics (a digest; models of
    one key fit one batch)."""
    import hashlib
    a = assembly
    h = hashlib.sha256(repr((a.rigid, a.large, a.zlaw, a.jlaw, a.monitor_names, tuple(numerics))).encode())
    for attr, cls in _CONTAINERS.values():
        c = getattr(a, attr)
        for f in cls._fields:
            if f not in K.PER_LANE[cls.__name__]:
                x = np.ascontiguousarray(getattr(c, f))
                h.update(repr((f, x.shape, x.dtype.str)).encode())
                h.update(x.tobytes())
    for x in (a.monitors.nodes, a.monitors.dof, a.monitors.group, a.gravity):
        h.update(np.ascontiguousarray(x).tobytes())
    return h.hexdigest()


def _inertia(mode, k, phys, free, alpha, safety):
    """Masses (or rotational inertias) of degrees of freedom with stiffness
    bounds ``k`` and physical values ``phys``, and the critical steps they
    imply ([] in quasi-static mode, where the masses follow from the step)."""
    if mode == QUASI_STATIC:
        return scaled_masses(k, alpha, safety), []
    mass = physical_masses(phys, free, "blocks.material.density")
    return mass, [critical_step(mass, k, alpha, free)]


def _rotations(a, mode, alpha, safety):
    """Rigid bodies: the inverse rotational inertias (quasi-static:
    isotropic, scaled from the rotational stiffness bound; dynamic: the
    principal moments, the smallest giving the critical step)."""
    free = a.bodies.rfixed.min(axis=1) == 0
    kr = a.rot_stiffness
    if np.any(free & (kr <= 0)):
        raise InputError("model", "a rigid block that may rotate carries no contact (no rotational stiffness)")
    imin, crit = _inertia(mode, kr, a.inertia.min(axis=1), free, alpha, safety)
    inertia = np.repeat(imin[:, None], 3, axis=1) if mode == QUASI_STATIC else \
        np.where(free[:, None], a.inertia, imin[:, None])
    iinv = np.zeros((a.n, 3, 3))
    for d in range(3):
        iinv[:, d, d] = 1.0 / inertia[:, d]
    return iinv, crit


def _ramp(controls):
    return 1.0 / controls.ramp_steps if controls.ramp_steps else 0.0


def begin(state, controls):
    """The state at the start of a stage under ``controls``: the velocity
    factor at zero when its velocities ramp up, else at one."""
    return state._replace(velocity_factor=0.0 if controls.ramp_steps else 1.0)


def started(state):
    """The state with its initial kinetic energy, set at its first advance."""
    if state.energy_in is not None:
        return state
    nodes = state.nodes
    free = nodes.fixed == 0
    return state._replace(energy_in=float(0.5 * np.sum((nodes.mass * nodes.v ** 2)[free])))


def advanced(state, controls, rows, finite):
    """(the new state, the History) of ``state`` after the rows of history
    (done, columns) its chunk under ``controls`` made; ``finite``: whether
    its last step was."""
    a = state.assembly
    done = rows.shape[0]
    ramp = _ramp(controls)
    # loading at full speed (the velocity ramp is over) at each step
    loading = state.velocity_factor + np.arange(1, done + 1) * ramp >= 1.0
    for g in range(len(a.monitor_names)):
        rows[:, K.h_disp(g)] /= max(1, int(np.sum(a.monitors.group == g)))
    state = state._replace(step=state.step + done, velocity_factor=min(1.0, state.velocity_factor + done * ramp),
                           finite=finite)
    return state, from_kernel(rows, loading, a.monitor_names)


def advance(state, controls, n):
    """Advances ``n`` steps (fewer if a step is not finite: the state says
    so) the one lane of a batch of one (lockstep.py advances larger
    batches).  Returns (the new state, the History of every step)."""
    batch = state.batch
    if batch.lanes != 1:
        raise ValueError("advance: a batch of several lanes advances by lockstep.run")
    state = started(state)
    batch.set_lane(state, controls)
    code, done, rows = batch.advance(n)
    return advanced(state, controls, np.ascontiguousarray(rows[:, :, 0]), code != K.ST_NONFINITE)


def prescribe(state, nodes, velocity):
    """The state with the prescribed velocity of ``nodes`` (indices, a mask
    or a slice) set to ``velocity`` (m per step or per second; it acts on
    their prescribed components only), in its lane."""
    state.nodes.vpres[nodes] = velocity
    return state


def prescribe_rotation(state, block, velocity):
    """The state with the prescribed angular velocity (global axes) of a
    rigid block whose rotation is prescribed (``Model.fix_rotation``)."""
    if not state.assembly.rigid:
        raise InputError(f"blocks[{block.id}]", "only rigid blocks rotate")
    bodies = state.bodies
    fixed = bodies.rfixed[block.node0] == 1
    w = np.asarray(velocity, float)
    if np.any(w[~fixed] != 0):
        raise InputError(f"blocks[{block.id}]", "only prescribed rotations take a velocity (Model.fix_rotation)")
    bodies.ompres[block.node0] = np.where(fixed, w, 0.0)
    return state


# --- what a state says ------------------------------------------------------
def zone_damage(state):
    """Tensile damage per tetrahedron: e_pt / e_ult in [0, 1]."""
    ept, eult = state.zones.state[:, K.ZS_EPT], state.zones.state[:, K.ZS_EULT]
    with np.errstate(invalid="ignore", divide="ignore"):
        d = np.where(eult > 0, ept / eult, 0.0)
    return np.clip(d, 0.0, 1.0)


def rotations(state):
    """Rotation angle (rad) of each rigid body."""
    tr = np.trace(state.bodies.R, axis1=1, axis2=2)
    return np.arccos(np.clip(0.5 * (tr - 1.0), -1.0, 1.0))


def _skew(grad):
    """Rotation vectors of the skew parts of displacement gradients (n, 3, 3)."""
    w = 0.5 * (grad - np.transpose(grad, (0, 2, 1)))
    return np.stack([w[:, 2, 1], w[:, 0, 2], w[:, 1, 0]], axis=1)


def max_rotation(state):
    """Largest rigid rotation (rad) of any block: of a rigid one its
    rotation angle; of a deformable one from the skew part of its
    volume-averaged displacement gradient (checks the small-displacement
    assumption)."""
    a, u = state.assembly, state.nodes.u
    if a.rigid:
        n = len(a.blocks)
        return float(rotations(state)[:n].max()) if n else 0.0
    z = state.zones
    t = z.tets
    du = u[t[:, 1:]] - u[t[:, :1]]                                   # (nt, 3, 3)
    omega = _skew(np.einsum("tai,taj->tij", du, z.dn.reshape(-1, 3, 3))) * (z.vol * z.wt)[:, None]
    out = 0.0
    for b, blk in enumerate(a.blocks):
        if blk.element == "zones":
            s, e = a.zone_ptr[b], a.zone_ptr[b + 1]
            vsum = np.sum(z.vol[s:e] * z.wt[s:e])
            out = max(out, float(np.linalg.norm(omega[s:e].sum(axis=0)) / vsum))
        else:           # a cell's displacement gradient at its centre: sum_a u_a (x) grad N_a
            h = (blk.hi - blk.lo) / blk.cells
            grads = (2.0 * np.array([[c & 1, (c >> 1) & 1, (c >> 2) & 1] for c in range(8)]) - 1.0) / (4.0 * h)
            grad = np.einsum("cai,aj->cij", u[a.cells.nodes[a.cell_ptr[b]:a.cell_ptr[b + 1]]], grads)
            out = max(out, float(np.linalg.norm(_skew(grad).mean(axis=0))))
    return out
