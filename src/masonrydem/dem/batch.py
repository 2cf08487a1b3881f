"""A batch: S simulations of one mesh, a lane each, advanced in lock-step
by the step kernel (kernels/layout.py: the lanes; lockstep.py: the
programs that drive them).  A single run is a batch of one
(init).  The lanes share the mesh's arrays; each has its own
materials, masses, states and controls.
"""
import hashlib

import numpy as np

from . import kernels as K
from .kernels.step import specialised
from .solver import State, checked_numerics, lane_arrays, ramp_rate

# container -> (its name in the Assembly, the kernels' class)
_CONTAINERS = dict(nodes=("nodes", K.Nodes), zones=("zones", K.Zones), cells=("cells", K.Cells),
                   joints=("joints", K.Contacts), bearings=("bearings", K.Contacts), bodies=("bodies", K.Bodies))


def init(assembly, numerics):
    """The state of ``assembly`` at rest, with its masses and step: the one
    lane of a batch of one."""
    return Batch(assembly, numerics, 1).load(0, assembly)


def width(runs):
    """The lanes of a batch for ``runs`` runs: one, or a multiple of eight
    (the kernels run eight lanes at a time: kernels/lanes.py)."""
    return 1 if runs <= 1 else 8 * -(-int(runs) // 8)


class Batch:
    """S simulations of one mesh, a lane each, advanced in lock-step by the
    step kernel: the kernels' containers with a lane axis on each run's
    own arrays (kernels/layout.py, PER_LANE), the mesh's arrays once.  S
    is one, or ``lanes`` rounded up to a multiple of eight.  ``load`` puts a
    run at rest into a lane, ``clear`` empties one (at rest, without loads:
    it computes zeros until loaded again).  Every lane's model must share
    the first's mesh, topology, constraints, laws and numerics (``fits``)."""

    def __init__(self, assembly, numerics, lanes):
        self.assembly, self.numerics, self.lanes = assembly, numerics, width(lanes)
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
                                 np.zeros((3, 3)), np.zeros((3, 3)), *_cell_space(nc, nk, S), np.zeros((4, S)),
                                 np.zeros(S))
        self.work = np.zeros((2, S))
        self.ctl = K.Controls(np.zeros(S, np.int64), np.zeros(S, np.int64), np.ones(S), np.ones(S), np.ones(S),
                              np.zeros(S), np.full(S, checked_numerics(numerics)[1]), a.gravity)
        self.kernel = None
        self.width = K.h_width(len(a.monitor_names))      # a row of history

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
        own, integ = lane_arrays(assembly, self.numerics)
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
        """Lane ``lane`` emptied: the first model at rest in it, without
        loads or prescribed velocities (every value it computes stays zero)."""
        self.load(lane, self.assembly)
        nodes, bodies = self.view("nodes", lane), self.view("bodies", lane)
        for x in (nodes.fext, nodes.vpres, nodes.mgrav, bodies.ompres, bodies.load_force):
            x[...] = 0.0
        self.ctl.lf[lane] = self.ctl.dvf[lane] = self.ctl.vf0[lane] = 0.0

    def narrowed(self, lanes):
        """A batch of the lanes ``lanes`` of this one (their arrays and
        controls copied, in that order; width(len(lanes)) lanes, the rest
        empty): a batch whose last runs leave lanes empty narrows, since an
        empty lane costs as much as a busy one."""
        new = Batch.__new__(Batch)
        new.__dict__.update(self.__dict__)
        S = width(len(lanes))
        idx = np.asarray(list(lanes) + [lanes[0]] * (S - len(lanes)))
        new.lanes = S
        new.containers = {}
        for name, c in self.containers.items():
            per = K.PER_LANE[type(c).__name__]
            if type(c) is K.Contacts:
                n = c.area.shape[0]
                rows = (np.arange(n)[:, None] * self.lanes + idx[None, :]).ravel()
                new.containers[name] = c._replace(**{f: np.asfortranarray(getattr(c, f)[rows]) for f in per})
            else:
                new.containers[name] = c._replace(**{f: np.ascontiguousarray(getattr(c, f)[..., idx]) for f in per})
        a, sc = self.assembly, self.scratch
        new.scratch = sc._replace(**dict(zip(("U", "F"), _cell_space(a.cells.nodes.shape[0], a.cells.K.shape[0], S))),
                                  sums=np.zeros((4, S)), vf=np.zeros(S))
        new.work = np.ascontiguousarray(self.work[:, idx])
        c = self.ctl
        new.ctl = c._replace(**{f: np.ascontiguousarray(getattr(c, f)[idx])
                                for f in ("step0", "k0", "dt", "lf", "vf0", "dvf", "alpha")})
        if S != self.lanes:         # the kernel is compiled for its number of lanes
            new.kernel = specialised(new.args(0))
        for b in range(len(lanes), S):
            new.clear(b)
        return new

    def args(self, n, hist=None):
        """The step kernel's arguments for ``n`` steps."""
        a, c = self.assembly, self.containers
        if hist is None:
            hist = np.empty((n, self.width, self.lanes))
        return (a.zlaw, a.jlaw, int(a.rigid), int(a.large), int(np.any(a.gravity != 0.0)), self.lanes, n, self.ctl,
                c["nodes"], c["zones"], c["cells"], c["joints"], c["bearings"], c["bodies"], a.monitors, hist, self.work,
                self.scratch)

    def set_lane(self, state, controls, k0=0):
        """The kernel's controls of ``state``'s lane for a chunk under
        ``controls``, ``k0`` of its steps done."""
        b, ctl = state.lane, self.ctl
        ctl.step0[b], ctl.k0[b], ctl.dt[b], ctl.alpha[b] = state.step, k0, state.integrator.dt, state.integrator.alpha
        ctl.lf[b], ctl.vf0[b], ctl.dvf[b] = float(controls.load_factor), float(state.velocity_factor), ramp_rate(controls)

    def advance(self, n):
        """Every lane ``n`` steps (fewer if a step of a lane is not
        finite): (steps done, the history rows (done, columns, S), whether
        each lane's last step was finite)."""
        args = self.args(n)
        _, done = self.kernel(*args)
        rows = args[15][:done]
        return done, rows, np.isfinite(rows[-1, K.H_KE]) & np.isfinite(rows[-1, K.H_RATIO])


def _cell_space(nc, nk, lanes):
    """The cells' work space (scratch U and F): a run's rows U (nc, 24),
    F (nk, nc, 24) for a batch of one (cells.py); none for more lanes,
    whose kernel works in registers (lanes.py)."""
    if lanes > 1:
        nc = 0
    return np.zeros((nc, 24)), np.zeros((nk, nc, 24))


def lane_key(assembly, numerics):
    """What the lanes of a batch share: the mesh, topology, constraints,
    monitors and laws of the model, and the numerics (a digest; models of
    one key fit one batch)."""
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


