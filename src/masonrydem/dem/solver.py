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


def checked_numerics(numerics):
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


def lane_arrays(assembly, numerics):
    """A run's own arrays at rest (by container and field, as the
    assembly's, without a lane axis) and its Integrator."""
    a = assembly
    mode, alpha, safety = checked_numerics(numerics)
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


def ramp_rate(controls):
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
    ramp = ramp_rate(controls)
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
    done, rows, finite = batch.advance(n)
    return advanced(state, controls, np.ascontiguousarray(rows[:, :, 0]), bool(finite[0]))


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
