"""The loading protocol of one simulation, as stage programs
(dem/lockstep.py): precompress the specimen, then load it under its test
(bending, tension or triplet shear, displacement controlled); ``judge``
says how the run ended, and ``simulation`` chains them into an Outcome
(row.py makes the row).  ``simulate`` builds a scene's specimen and runs
its simulation alone; ``simulate_many`` runs many scenes, those of one
mesh in the lanes of a batch.  docs/formulation.md, sections 9 and 10:
stop rules and peaks.
"""
import math
import sys
import time
from typing import NamedTuple

import numpy as np

from ..dem import PEAK_UNBALANCE, Batch, Controls, Stops, init, lane_key, lockstep, prescribe, stage, unbalance
from .build import build

GOOD = ("load_drop", "displacement_limit", "past_peak")
CHUNK = 500          # steps between the stop rules' checks


class Stage(NamedTuple):
    """A stage's Record (stops.Record) and Ending (stops.Ending)."""
    record: object
    ending: object


class Outcome(NamedTuple):
    """A simulation: its specimen and final state, the two stages (the
    precompression None without one; the test None when the
    precompression failed), the test's start (u0: the load line's
    displacement, start: the step), and the judged status and message."""
    specimen: object
    state: object
    precompression: Stage
    test: Stage
    u0: float
    start: int
    status: str
    message: str
    wall_time: float


class Progress:
    """A stage's progress on ``stream``: a line when it starts and when it
    ends; in between, on a terminal, a bar redrawn in place (the share of
    the way: the load line's displacement over max_displacement, or the
    unbalanced-force ratio's way down to ratio_tol on a log scale), and
    elsewhere (a log) a line every ``every`` seconds."""

    def __init__(self, stage, share, u0=0.0, every=2.0, stream=None):
        stream = stream if stream is not None else sys.stderr
        self.stage, self.share, self.u0, self.stream = stage, share, u0, stream
        self.tty = stream.isatty()
        self.every = 0.2 if self.tty else every
        self.t0 = self.last = time.perf_counter()
        print(f"[{stage}] started", file=stream, flush=True)

    def _line(self, state, history):
        P, u = (history.force[-1, 0], history.disp[-1, 0]) if history.monitors else (0.0, 0.0)
        return (f"[{self.stage}] step {state.step:8d}  load {P / 1e3:8.3f} kN  disp {(u - self.u0) * 1e3:7.4f} mm"
                f"  ratio {history.ratio[-1]:.2e}  ({time.perf_counter() - self.t0:.0f} s)")

    def __call__(self, state, history):
        now = time.perf_counter()
        if now - self.last < self.every:
            return
        self.last = now
        if not self.tty:
            print(self._line(state, history), file=self.stream, flush=True)
            return
        done = min(max(self.share(history), 0.0), 1.0)
        bar = "#" * round(20 * done) + "." * (20 - round(20 * done))
        print(f"\r{self._line(state, history)}  [{bar}] {done:4.0%}", end="", file=self.stream, flush=True)

    def end(self, state, ending):
        clear = "\r\x1b[K" if self.tty else ""      # the bar's line, rewritten
        print(f"{clear}[{self.stage}] {ending.status} at step {state.step}: "
              f"{ending.message} ({time.perf_counter() - self.t0:.1f} s)", file=self.stream, flush=True)


def _stage(name, progress, share, u0=0.0):
    """The stage's Progress, or None without progress."""
    return Progress(name, share, u0) if progress else None


def precompress(state, specimen, progress=False):
    """The precompression stage (a program): the applied pressure at rest,
    run until the unbalanced-force ratio falls below ratio_tol (or
    max_steps)."""
    pre, num = specimen.scene.loading.precompression, specimen.scene.discretization
    shown = _stage("precompression", progress, lambda h: math.log10(max(h.ratio[-1], 1e-300)) / math.log10(pre.ratio_tol))
    state, record, ending = yield from stage(state, pre.max_steps, Stops(ratio_tol=pre.ratio_tol), chunk=CHUNK,
                                             record_every=num.record_every, progress=shown)
    if shown:
        shown.end(state, ending)
    return state, Stage(record, ending)


def load(state, specimen, u0, progress=False):
    """The test stage (a program): the drive moves at its rate (after a ramp) until the
    load line has moved max_displacement from u0, or the load has fallen
    below load_drop of its peak (or max_steps).  A peak counts near
    equilibrium, the load balanced by the supports (history.py)."""
    drive, num = specimen.scene.loading.drive, specimen.scene.discretization
    state = prescribe(state, specimen.drive, specimen.velocity)
    stops = Stops(disp_limit=u0 + drive.max_displacement, load_drop=drive.load_drop, monitor="load",
                  balance="support", past_peak=drive.past_peak)
    shown = _stage(specimen.test, progress, lambda h: (h.disp[-1, 0] - u0) / drive.max_displacement, u0)
    state, record, ending = yield from stage(state, drive.max_steps, stops, Controls(ramp_steps=drive.ramp_steps),
                                             chunk=CHUNK, record_every=num.record_every, progress=shown)
    if shown:
        shown.end(state, ending)
    return state, Stage(record, ending)


def judge(pre, test, peak, ramp_load, scene):
    """(status, message) of a run from its stages' Endings (``pre`` None
    without a precompression; ``test`` None when it failed), the test's
    Peak of the load (None: none counted) and the largest load within the
    velocity ramp.  Beyond the test's own ending:

    * no_peak: the test ended well, but no load was ever near equilibrium;
    * peak_in_ramp: the load peaked within the ramp, where a peak does not
      count (a run that reached its stop criteria would report a later,
      lower load as its peak);
    * precompression_unconverged: the test ended well on a wall that the
      precompression left out of equilibrium: it measured nothing."""
    end = test if test is not None else pre
    status, message = end.status, end.message
    drive = scene.loading.drive
    if end.status in GOOD and peak is None:
        status, message = "no_peak", (f"the load was never within {PEAK_UNBALANCE:.0%} of balanced after the "
                                      "velocity ramp: no peak counts (lower the rate)")
    if end.status in GOOD and ramp_load is not None and not ramp_load <= (peak.load if peak else math.nan):
        status, message = "peak_in_ramp", (f"the load peaked at {ramp_load / 1e3:.4g} kN within the velocity ramp "
                                           f"(the first {drive.ramp_steps} steps), where a peak does not count: "
                                           "lower the rate or the ramp steps")
    if pre is not None and pre.status == "max_steps" and status in GOOD:
        status, message = "precompression_unconverged", (
            f"the precompression did not reach equilibrium ({pre.message} with the unbalanced-force ratio above "
            f"loading.precompression.ratio_tol, {scene.loading.precompression.ratio_tol:g}); the {scene.loading.test} "
            f"stage then ended with {end.status}: {end.message}")
    return status, message


def simulate(scene, progress=True):
    """Runs a typed scene alone: builds its specimen, then its
    ``simulation``.  Returns an Outcome."""
    t0 = time.perf_counter()
    specimen = build(scene)
    if progress:
        a = specimen.assembly
        print(f"[build] {len(specimen.units)} units, {len(specimen.joints)} joints: {a.zones.tets.shape[0]} tetrahedra, "
              f"{a.cells.nodes.shape[0]} linear cells, {a.joints.area.size} sub-contacts ({time.perf_counter() - t0:.1f} s)",
              file=sys.stderr, flush=True)
    return lockstep.drive(simulation(specimen, init(specimen.assembly, specimen.numerics), progress, t0))


def simulation(specimen, state, progress=False, t0=None):
    """A specimen's simulation from its state at rest (a program,
    dem/lockstep.py): precompresses it (if it has a pressure), loads it if
    the precompression converged or ran its steps, and judges the run.
    Returns an Outcome; its wall time from ``t0`` (None: now)."""
    t0 = time.perf_counter() if t0 is None else t0
    scene = specimen.scene
    pre = test = None
    u0 = 0.0
    if scene.loading.precompression.pressure > 0:
        state, pre = yield from precompress(state, specimen, progress)
        u0 = float(pre.record.last.disp_of("load")[0])
    start = state.step
    if pre is None or pre.ending.status in ("converged", "max_steps"):
        state, test = yield from load(state, specimen, u0, progress)
    peak = test.record.peaks[test.record.history.group("load")] if test is not None else None
    ramp_load = None
    if test is not None:
        h = test.record.history
        ramp = h.force_of("load")[h.step <= start + scene.loading.drive.ramp_steps]
        ramp_load = float(ramp.max()) if ramp.size else None
    status, message = judge(pre and pre.ending, test and test.ending, peak, ramp_load, scene)
    return Outcome(specimen, state, pre, test, u0, start, status, message, time.perf_counter() - t0)


def simulate_many(scenes, finish, lanes):
    """Runs the typed ``scenes`` quietly, those that share a mesh and
    numerics in the lanes of a batch (at most ``lanes`` at a time), and
    calls ``finish(index, outcome, error)`` for each as it ends (error:
    the exception of a scene that could not be built or run, outcome
    None), while its state is still in its lane.  Each scene's Outcome is
    the one ``simulate`` gives, bit for bit.  Specimens are built as lanes
    need them; one whose mesh differs from the batch's is kept for a batch
    of its own."""
    pending = list(enumerate(scenes))[::-1]      # popped from the end: in order
    held = []                                    # built, for a later batch: (i, specimen, key, t0)

    def built():
        """The next specimen in order, (i, specimen, key, t0), or None."""
        while pending:
            i, scene = pending.pop()
            t0 = time.perf_counter()
            try:
                specimen = build(scene)
                return i, specimen, lane_key(specimen.assembly, specimen.numerics), t0
            except Exception as e:      # nothing lost: the scene's row says why
                finish(i, None, e)
        return None

    def job(i, specimen, t0):
        return lockstep.Job(specimen.assembly, lambda state: simulation(specimen, state, False, t0),
                            lambda outcome, error: finish(i, outcome, error))

    while True:
        first = held.pop(0) if held else built()
        if first is None:
            return
        key = first[2]
        batch = Batch(first[1].assembly, first[1].numerics, min(lanes, 1 + len(pending) + len(held)))

        def jobs():
            yield job(first[0], first[1], first[3])
            for h in [h for h in held if h[2] == key]:
                held.remove(h)
                yield job(h[0], h[1], h[3])
            while (nxt := built()) is not None:
                if nxt[2] == key:
                    yield job(nxt[0], nxt[1], nxt[3])
                else:
                    held.append(nxt)
        lockstep.run(batch, jobs())


DROP_WINDOW = 1e-4   # m: the post-peak branch a row describes (drop_after_peak, post_peak)


def post_peak(outcome):
    """Within DROP_WINDOW after the peak of the test's load: the largest
    unbalance of the load (did it stay near equilibrium, or snap: a sudden
    crack that displacement control cannot follow, carried by inertia);
    and the history's unbalance column.  The window is the branch every
    run reaches (a run that stops once its peak is certain goes at least
    that far: stops.Stops.past_peak)."""
    h = outcome.test.record.history if outcome.test is not None else None
    if h is None:
        return math.nan, None
    g = h.group("load")
    u = unbalance(h, g, h.group("support"))
    peak = outcome.test.record.peaks[g]
    after = u[(h.step > peak.step) & (h.disp[:, g] <= peak.disp + DROP_WINDOW)] if peak is not None else u[:0]
    return (float(np.nanmax(after)) if after.size else math.nan), u
