"""Explicit time integration of a built model: quasi-static (density
scaling, local damping) or dynamic (physical masses), histories, stop
criteria and a divergence guard.
"""
import math
import time
from dataclasses import dataclass, field

import numpy as np

from . import kernels as K
from .errors import InputError

QUASI_STATIC = "quasi-static"
DYNAMIC = "dynamic"
# a load counts as a peak only near equilibrium, below this unbalanced-force
# ratio (10 % of the applied force unbalanced): see History
PEAK_RATIO = 0.1


@dataclass
class RunResult:
    """Outcome of ``Solver.run``.

    status: 'converged' (unbalanced-force ratio below tolerance),
    'displacement_limit', 'load_drop', 'max_steps', 'diverged' or
    'large_displacement' (beyond the small-displacement formulation); message
    says why and, for a divergence, where it started."""
    status: str
    message: str
    steps: int
    wall_time: float


@dataclass
class History:
    """Decimated histories (every ``every`` steps, all runs, plus each
    chunk's row of peak load, so that the exact peak is a recorded row)
    and the exact peaks of the current (last) run, i.e. of the current
    loading stage.

    A peak is the largest load reached near equilibrium, at an unbalanced-
    force ratio below ``PEAK_RATIO``, once the velocity ramp is over: a load
    carried while the model is far from equilibrium is inertia, not
    strength.  Measured: the start-up transient of stiff loading strips
    (12x6x6 cells per unit: 2.3 kN at a ratio of 1.2 after 250 steps,
    against a 13 kN peak; under precompression the same spike shows a low
    ratio, the precompression dominating the applied forces, hence the
    ramp), and the snap-back of brittle units (G_f = 5 N/m: 35 kN at a
    ratio of 0.7 after a brick cracked at 21.8 kN in equilibrium)."""
    every: int
    rows: list = field(default_factory=list)
    peak: dict = field(default_factory=dict)       # group -> (load, disp, step, ratio)

    def array(self):
        return np.concatenate(self.rows) if self.rows else np.zeros((0, 0))


class Solver:
    """Explicit central differences with Cundall's local damping.

    The critical step counts the damping: local damping multiplies a force
    that opposes the velocity by (1 + alpha), and in the highest mode (the
    displacements alternate in sign every step) every force opposes the
    velocity, so central differences are stable for
    dt < dt_crit = 2 min sqrt(m_i / ((1 + alpha) k_i)), with k_i a
    Gershgorin bound of the nodal stiffness (zones and contacts): exactly
    the limit for one degree of freedom (tests/test_stability.py), and
    conservative otherwise.  Without the (1 + alpha) the usual criterion
    2 sqrt(m / k) lets alpha = 0.8 runs diverge from 0.75 of that step.

    mode 'quasi-static': time step dt = 1 (pseudo-time; velocities are
    displacements per step) and density scaling: nodal masses
    m_i = (1 + alpha) k_i (dt / (2 s))^2, so that dt = s dt_crit with the
    safety factor s in (0, 1].  Damping alpha = 0.8 by default.

    mode 'dynamic': physical lumped masses, dt given (default: s times the
    critical step); a dt above the critical step is refused.  No damping by
    default.

    The formulation is small-displacement (strains on the initial geometry,
    joints with fixed axes): ``run`` stops with status
    'large_displacement' when a block rotates by more than
    ``rotation_limit`` radians (checked every 20 chunks).
    """

    def __new__(cls, model, *args, **kwargs):
        """A model of rigid blocks gets the rigid-block solver."""
        if cls is Solver and model.rigid:
            cls = RigidSolver
        return super().__new__(cls)

    def __init__(self, model, mode=QUASI_STATIC, damping=None, safety=0.9, dt=None,
                 chunk=200, record_every=10, rotation_limit=0.05):
        if mode not in (QUASI_STATIC, DYNAMIC):
            raise InputError("solver.mode", f"must be {QUASI_STATIC!r} or {DYNAMIC!r}, got {mode!r}")
        if not (isinstance(safety, (int, float)) and 0 < safety <= 1):
            raise InputError("solver.safety", f"must be in (0, 1], got {safety!r}")
        if damping is None:
            damping = 0.8 if mode == QUASI_STATIC else 0.0
        if not (0.0 <= damping < 1.0):
            raise InputError("solver.damping", f"must be in [0, 1), got {damping!r}")
        self.model = model
        self.rotation_limit = float(rotation_limit)
        self.b = b = model.build()
        nn = b["nn"]
        free = b["fixed"].min(axis=1) == 0
        k = b["stiffness"]
        floating = np.flatnonzero(free & (k <= 0))
        if floating.size:
            raise InputError("model", f"{floating.size} free nodes carry no stiffness "
                             f"(first: node {floating[0]})")
        self.mode = mode
        self.alpha = float(damping)
        self._safety, self._dt_arg = safety, dt
        self.mass = self._inertias(k, b["mphys"], free, safety, dt)
        self.u = np.zeros((nn, 3))
        self.v = np.zeros((nn, 3))
        self.f = np.zeros((nn, 3))
        self.js = b["joints"]["state"].copy()
        self.bs = b["bearings"]["state"].copy()
        self.fixed = b["fixed"].copy()
        self.vpres = b["vpres"].copy()
        self.gravity = np.asarray(model.gravity, float).copy()
        self.load_factor = 1.0
        self.work = np.zeros(2)   # work done on the model since the start, its largest value
        self.energy_in = None     # initial kinetic energy + work (set at the first step)
        # omega_max dt / 2 without damping: the step against the undamped critical step
        self._c = min(self.dt / self.dt_crit / math.sqrt(1.0 + self.alpha), 0.999)
        self.velocity_factor = 1.0
        self._ramp = 0.0          # velocity-factor increment per step
        self.step = 0
        self.chunk = int(chunk)
        self.ngrp = len(model.monitors)
        self.history = History(int(record_every))
        self.last = np.zeros(2 + 2 * self.ngrp)
        self._setup_blocks()

    def _inertias(self, k, phys, free, safety, dt):
        """Masses (or rotational inertias) of degrees of freedom with
        stiffness bounds ``k`` and physical values ``phys``; sets dt and
        dt_crit (quasi-static: scaled, dt = 1; dynamic: physical, the step
        checked against the critical step)."""
        if self.mode == QUASI_STATIC:
            self.dt = 1.0
            self.dt_crit = self.dt / safety
            return np.where(k > 0, (1.0 + self.alpha) * k * (self.dt / (2.0 * safety)) ** 2, 1.0)
        mass = phys.copy()
        if np.any(free & (mass <= 0)):
            raise InputError("blocks.material.density", "dynamic mode needs a positive density for every block")
        mass[~free] = np.where(mass[~free] > 0, mass[~free], 1.0)
        with np.errstate(divide="ignore"):
            crit = float(np.min(2.0 * np.sqrt(mass[free] / ((1.0 + self.alpha) * k[free])), initial=np.inf))
        self.dt_crit = min(getattr(self, "dt_crit", np.inf), crit)
        if dt is None:
            dt = safety * self.dt_crit
        if not (dt > 0) or dt > self.dt_crit:
            raise InputError("solver.dt", f"time step {dt!r} s is above the critical step "
                             f"{self.dt_crit:.6g} s (2 min sqrt(m / ((1 + damping) k))) or not positive")
        self.dt = float(dt)
        return mass

    def _setup_blocks(self):
        """The zones' state and scratch arrays (deformable blocks)."""
        b = self.b
        nt = b["tets"].shape[0]
        self.stress = np.zeros((nt, 6))
        self.zs = np.zeros((nt, K.N_ZS))
        gsize = np.diff(b["gptr"]).max() if nt else 1
        self._scratch = (np.zeros((gsize, 6)), np.zeros(gsize), np.zeros((max(nt, 1), 2), np.int64),
                         np.zeros((3, 3)), np.zeros((3, 3)))
        # smallest zone size, for the divergence guard
        self.h_min = float(np.min(np.cbrt(6.0 * b["vol"]))) if nt else 1.0

    # --- controls -------------------------------------------------------
    @property
    def gravity_on(self):
        """1 when the model has gravity: the kernels are compiled with or
        without it."""
        return int(np.any(self.gravity != 0.0))

    def monitor_index(self, name):
        for g, (n, _, _) in enumerate(self.model.monitors):
            if n == name:
                return g
        raise InputError("monitor", f"no monitor named {name!r}")

    # --- stepping -------------------------------------------------------
    def cycle(self, nsteps):
        """Advances ``nsteps`` steps; returns (status code, steps done)."""
        b = self.b
        hist = np.empty((nsteps, 2 + 2 * self.ngrp))
        if self.energy_in is None:
            free = self.fixed == 0
            self.energy_in = float(0.5 * np.sum((self.mass[:, None] * self.v ** 2)[free]))
        status, done = self._kernel(nsteps, hist)
        hist = hist[:done]
        # loading at full speed (the velocity ramp is over) at each step
        loading = self.velocity_factor + np.arange(1, done + 1) * self._ramp >= 1.0
        self.velocity_factor = min(1.0, self.velocity_factor + done * self._ramp)
        for g in range(self.ngrp):
            hist[:, 3 + 2 * g] /= max(1, int(np.sum(b["mon_grp"] == g)))
        self._record(hist, loading)
        self.step += done
        return status, done

    def _kernel(self, nsteps, hist):
        b = self.b
        j, br = b["joints"], b["bearings"]
        return K.run_chunk_entry(
            b["zlaw"], b["jlaw"], self.gravity_on, nsteps, self.dt, self.alpha, self.load_factor,
            self.velocity_factor, self._ramp, self.gravity,
            self.u, self.v, self.f, self.mass, b["mphys"], self.fixed, self.vpres, b["fext"], b["x0"],
            b["tets"], b["dn"], b["vol"], b["wt"], b["gptr"], b["gnodes"], b["gnptr"],
            b["zp"], self.zs, self.stress,
            j["nodes"], j["cnt"], j["w"], j["axes"], j["area"], j["par"], self.js,
            br["nodes"], br["cnt"], br["w"], br["axes"], br["area"], br["par"], self.bs,
            b["mon_nodes"], b["mon_dir"], b["mon_grp"], hist, self.work, *self._scratch)

    def _record(self, hist, loading):
        h = self.history
        if hist.shape[0] == 0:
            return
        idx = np.arange(self.step, self.step + hist.shape[0])
        keep = (idx + 1) % h.every == 0
        keep[-1] = True
        balanced = (hist[:, 0] < PEAK_RATIO) & loading
        for g in range(self.ngrp if balanced.any() else 0):   # each chunk's peak is a recorded row
            i = int(np.argmax(np.where(balanced, hist[:, 2 + 2 * g], -np.inf)))
            keep[i] = True
            load = hist[i, 2 + 2 * g]
            if g not in h.peak or load > h.peak[g][0]:
                h.peak[g] = (float(load), float(hist[i, 3 + 2 * g]), int(idx[i] + 1), float(hist[i, 0]))
        h.rows.append(np.column_stack([idx[keep] + 1, hist[keep]]))
        self.last = hist[-1]

    def _diverged_where(self):
        """Where a blow-up started: the node with a non-finite or the largest
        velocity, and its block."""
        with np.errstate(over="ignore", invalid="ignore"):
            speed = np.sqrt(np.sum(self.v ** 2, axis=1))
        bad = np.flatnonzero(~np.isfinite(speed))
        nd = int(bad[0]) if bad.size else int(np.argmax(speed))
        blk = int(self.b["block_of_node"][nd])
        return f"node {nd} (block {blk}, at {np.round(self.b['x0'][nd], 4).tolist()} m)"

    def _divergence(self, code, high_ratio_chunks):
        """Why the run diverged, or None: non-finite values; a node moving
        more than 10 % of the smallest zone size in one step; an energy
        blow-up: kinetic energy above 10 / (1 - c) times the most energy
        put in so far (the initial kinetic energy plus the work of
        reactions and applied forces).  A stable run cannot exceed
        E / (1 - c): central differences conserve, per mode of frequency
        omega, a quadratic form that bounds 1/2 m v^2 from below by
        (1 - c) times it, c = omega dt / 2 < 1 (at most ``_c``); measured
        near the critical step, 1/2 m v^2 exceeds the energy put in (and
        the work to u(t+dt) can be negative).  In quasi-static mode: also
        an unbalanced-force ratio above 10 for 5 chunks in a row."""
        if code == K.ST_NONFINITE:
            return "non-finite values"
        vmax = float(np.max(np.abs(self.v))) * self.dt
        if vmax > 0.1 * self.h_min:
            return f"a node moved {vmax:.3g} m in one step (> 10% of the smallest zone, {self.h_min:.3g} m)"
        energy_max = self.energy_in + self.work[1]
        ke, limit = self.last[1], 10.0 * energy_max / (1.0 - self._c)
        if ke > limit:
            return (f"energy blow-up: kinetic energy {ke:.3g} J exceeds {limit:.3g} J (10 x the most energy put in, "
                    f"{energy_max:.3g} J, / (1 - {self._c:.3g}))")
        if high_ratio_chunks >= 5:
            return f"unbalanced-force ratio above 10 for 5 chunks ({self.last[0]:.3g})"
        return None

    def run(self, max_steps, ratio_tol=None, disp_limit=None, load_drop=None,
            monitor=None, progress=None, ramp_steps=0):
        """Cycles until a stop criterion holds:

        * ratio_tol: the unbalanced-force ratio fell below it ('converged');
        * disp_limit: |mean displacement| of ``monitor`` reached it;
        * load_drop: after the peak, the load of ``monitor`` fell below
          load_drop * peak (a peak is reached near equilibrium: History);
        * max_steps;
        * the divergence guard ('diverged', see ``_divergence``);
        * a block rotation beyond ``rotation_limit`` ('large_displacement').
        ramp_steps: the prescribed velocities grow linearly from zero to their
        full value over the first ``ramp_steps`` steps of this run.
        Peaks (``history.peak``) are those of this run.
        ``progress(solver)`` is called after every chunk."""
        t0 = time.perf_counter()
        g = self.monitor_index(monitor) if monitor is not None else None
        if (disp_limit is not None or load_drop is not None) and g is None:
            raise InputError("run.monitor", "displacement and load-drop criteria need a monitor")
        start = self.step
        self.history.peak = {}
        if ramp_steps:
            self.velocity_factor, self._ramp = 0.0, 1.0 / ramp_steps
        else:
            self.velocity_factor, self._ramp = 1.0, 0.0
        status, message = "max_steps", f"reached {max_steps} steps"
        chunks = 0
        high_ratio = 0
        while self.step - start < max_steps:
            chunks += 1
            n = min(self.chunk, max_steps - (self.step - start))
            code, _ = self.cycle(n)
            if progress is not None:
                progress(self)
            high_ratio = high_ratio + 1 if self.mode == QUASI_STATIC and self.last[0] > 10 else 0
            reason = self._divergence(code, high_ratio)
            if reason:
                status, message = "diverged", (f"{reason} at step {self.step}, "
                                               f"starting at {self._diverged_where()}")
                break
            if chunks % 20 == 0 and (rot := self.max_rotation()) > self.rotation_limit:
                status, message = "large_displacement", (
                    f"a block rotated by {rot:.3g} rad (> {self.rotation_limit}) at step {self.step}: "
                    "beyond the small-displacement formulation")
                break
            if ratio_tol is not None and self.last[0] < ratio_tol:
                status, message = "converged", f"unbalanced-force ratio {self.last[0]:.3g} < {ratio_tol}"
                break
            if g is not None:
                load, disp = self.last[2 + 2 * g], self.last[3 + 2 * g]
                if disp_limit is not None and abs(disp) >= disp_limit:
                    status, message = "displacement_limit", f"displacement {disp:.6g} m reached"
                    break
                peak = self.history.peak.get(g, (0.0,))[0]
                if load_drop is not None and peak > 0 and load < load_drop * peak:
                    status, message = "load_drop", f"load fell to {load / peak:.3f} of the peak"
                    break
        return RunResult(status, message, self.step - start, time.perf_counter() - t0)

    # --- results ----------------------------------------------------------
    def zone_damage(self):
        """Tensile damage per tetrahedron: e_pt / e_ult in [0, 1]."""
        ept, eult = self.zs[:, K.ZS_EPT], self.zs[:, K.ZS_EULT]
        with np.errstate(invalid="ignore", divide="ignore"):
            d = np.where(eult > 0, ept / eult, 0.0)
        return np.clip(d, 0.0, 1.0)

    def joint_state(self):
        return self.js

    def max_rotation(self):
        """Largest rigid rotation (rad) of any block, from the skew part of
        the volume-averaged displacement gradient (checks the
        small-displacement assumption)."""
        b = self.b
        t = b["tets"]
        du = self.u[t[:, 1:]] - self.u[t[:, :1]]                    # (nt, 3, 3)
        g = b["dn"].reshape(-1, 3, 3)                                # rows: grad N_a
        grad = np.einsum("tai,taj->tij", du, g)                      # du_i/dx_j
        w = 0.5 * (grad - np.transpose(grad, (0, 2, 1)))
        omega = np.stack([w[:, 2, 1], w[:, 0, 2], w[:, 1, 0]], axis=1) * (b["vol"] * b["wt"])[:, None]
        out = 0.0
        start = 0
        for blk in self.model.blocks:
            n = blk.mesh.tets.shape[0]
            vsum = np.sum(b["vol"][start:start + n] * b["wt"][start:start + n])
            out = max(out, float(np.linalg.norm(omega[start:start + n].sum(axis=0)) / vsum))
            start += n
        return out


class RigidSolver(Solver):
    """The solver of a model of rigid blocks (``Solver(model)`` returns it):
    six degrees of freedom per block, the translations as the nodes of
    ``Solver`` and three rotations besides (orientation R, angular velocity
    om, moment mom); kernel ``kernels.run_chunk_rigid``.  No zones: nothing
    of the zone kernel is allocated or compiled.  Rotational inertias like
    the masses: scaled from the Gershgorin bound of the rotational stiffness
    (quasi-static: isotropic) or physical (dynamic: principal moments),
    the critical step the smaller of translations and rotations.  With
    ``model.large`` the rotation limit is off: the joints' axes turn with
    their blocks."""

    def _setup_blocks(self):
        b = self.b
        nn = b["nn"]
        free = b["rfixed"].min(axis=1) == 0
        kr = b["rot_stiffness"]
        if np.any(free & (kr <= 0)):
            raise InputError("model", "a rigid block that may rotate carries no contact (no rotational stiffness)")
        if self.mode == QUASI_STATIC:
            inertia = np.repeat(self._inertias(kr, kr, free, self._safety, self._dt_arg)[:, None], 3, axis=1)
        else:
            imin = self._inertias(kr, b["inertia"].min(axis=1), free, self._safety, self._dt_arg)
            inertia = np.where(free[:, None], b["inertia"], imin[:, None])
            self._c = min(self.dt / self.dt_crit / math.sqrt(1.0 + self.alpha), 0.999)
        self.iinv = np.zeros((nn, 3, 3))
        for d in range(3):
            self.iinv[:, d, d] = 1.0 / inertia[:, d]
        self.ompres = b["ompres"].copy()
        self.R = np.repeat(np.eye(3)[None], nn, axis=0)
        self.om = np.zeros((nn, 3))
        self.mom = np.zeros((nn, 3))
        self._fl = np.zeros((nn, 3))
        if b["large"]:
            self.rotation_limit = np.inf
        self.h_min = float(np.min(b["rlen"]))

    def _kernel(self, nsteps, hist):
        b = self.b
        j, br = b["joints"], b["bearings"]
        return K.run_chunk_rigid_entry(
            b["jlaw"], b["large"], self.gravity_on, nsteps, self.dt, self.alpha, self.load_factor,
            self.velocity_factor, self._ramp, self.gravity,
            self.u, self.v, self.f, self.mass, b["mphys"], self.fixed, self.vpres,
            self.R, self.om, self.mom, self.iinv, b["rfixed"], self.ompres, b["rlen"], self._fl,
            b["pl_body"], b["pl_lever"], b["pl_force"],
            j["body"], j["lever"], j["axes"], j["area"], j["par"], self.js,
            br["body"], br["lever"], br["axes"], br["area"], br["par"], self.bs,
            b["mon_nodes"], b["mon_dir"], b["mon_grp"], hist, self.work)

    def set_angular_velocity(self, block, velocity):
        """The prescribed angular velocity (global axes) of a block whose
        rotation is prescribed (``Model.fix_rotation``)."""
        fixed = self.b["rfixed"][block.node0] == 1
        w = np.asarray(velocity, float)
        if np.any(w[~fixed] != 0):
            raise InputError(f"blocks[{block.id}]", "only prescribed rotations take a velocity (Model.fix_rotation)")
        self.ompres[block.node0] = np.where(fixed, w, 0.0)

    def zone_damage(self):
        return np.zeros(0)

    def rotations(self):
        """Rotation angle (rad) of each body."""
        tr = np.trace(self.R, axis1=1, axis2=2)
        return np.arccos(np.clip(0.5 * (tr - 1.0), -1.0, 1.0))

    def max_rotation(self):
        n = len(self.model.blocks)
        return float(self.rotations()[:n].max()) if n else 0.0
