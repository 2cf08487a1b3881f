"""Running a stage: advance in chunks until a stop rule holds.

``stage`` is the stage as a program (lockstep.py): a generator that
yields each chunk's lockstep.Advance and is sent back the advanced state
and its History, so that one simulation runs alone (``run``) or in a
lane of a batch beside others, by the same code.

The stop rules and the divergence guard are small pure functions of the
state, the chunk's last row and the peak; ``run`` applies them in order
after every chunk (docs/formulation.md, section 9):

* the divergence guard ('diverged');
* a block rotation beyond the state's rotation limit ('large_displacement'),
  checked every 20 chunks;
* the unbalanced-force ratio below ``ratio_tol`` ('converged');
* the monitor's mean displacement reaching ``disp_limit``
  ('displacement_limit');
* after its peak, the monitor's load below ``load_drop`` times the peak
  ('load_drop');
* past its peak, the peak certain ('past_peak'): the monitor has moved
  ``after`` beyond the peak's displacement and its load, balanced, is
  ``drop`` below the peak, or it has moved ``at_most`` beyond it;
* ``max_steps`` ('max_steps').
"""
import time
from typing import NamedTuple

import numpy as np

from ..errors import InputError
from .history import PEAK_UNBALANCE, chunk_peaks, concat, decimate, higher
from .lockstep import Advance, drive
from .solver import Controls, begin, max_rotation
from .stability import QUASI_STATIC


class Stops(NamedTuple):
    """The stop rules of a stage.  ``monitor``: the monitor whose load and
    displacement the displacement and load-drop rules read; ``balance``:
    the monitor whose reaction balances its load in a static state (its
    peak then counts when the load's own unbalance is small)."""
    ratio_tol: float = None
    disp_limit: float = None
    load_drop: float = None
    monitor: str = None
    balance: str = None
    past_peak: tuple = None     # (drop, after, at_most)


class Ending(NamedTuple):
    """How a stage ended: status ('converged', 'displacement_limit',
    'load_drop', 'max_steps', 'diverged' or 'large_displacement'), why,
    its steps and wall time."""
    status: str
    message: str
    steps: int
    wall_time: float


class Record(NamedTuple):
    """What a stage leaves: its History decimated (every ``record_every``-th
    step, each chunk's last row and each chunk's peak rows), the last row
    of its last chunk, and per monitor group its Peak (None if none)."""
    history: object
    last: object
    peaks: tuple


def divergence(state, last, high_ratio_chunks):
    """Why the run diverged, or None: a step that was not finite; a node
    moving more than 10 % of the smallest zone size in one step; an
    energy blow-up: kinetic energy above 10 / (1 - c) times the most
    energy put in so far (the initial kinetic energy plus the work of
    reactions and applied forces; central differences bound the kinetic
    energy of a stable run by E / (1 - c), c = omega dt / 2 < 1); in
    quasi-static mode also an unbalanced-force ratio above 10 for 5
    chunks in a row."""
    integ = state.integrator
    if not state.finite:
        return "non-finite values"
    vmax = float(np.max(np.abs(state.nodes.v))) * integ.dt
    if vmax > 0.1 * integ.h_min:
        return f"a node moved {vmax:.3g} m in one step (> 10% of the smallest zone, {integ.h_min:.3g} m)"
    energy_max = state.energy_in + state.work[1]
    ke, limit = last.kinetic_energy[0], 10.0 * energy_max / (1.0 - integ.c)
    if ke > limit:
        return (f"energy blow-up: kinetic energy {ke:.3g} J exceeds {limit:.3g} J (10 x the most energy put in, "
                f"{energy_max:.3g} J, / (1 - {integ.c:.3g}))")
    if high_ratio_chunks >= 5:
        return f"unbalanced-force ratio above 10 for 5 chunks ({last.ratio[0]:.3g})"
    return None


def diverged_where(state):
    """Where a blow-up started: the node with a non-finite or the largest
    velocity, and its block."""
    with np.errstate(over="ignore", invalid="ignore"):
        speed = np.sqrt(np.sum(state.nodes.v ** 2, axis=1))
    bad = np.flatnonzero(~np.isfinite(speed))
    nd = int(bad[0]) if bad.size else int(np.argmax(speed))
    blk = int(state.assembly.block_of_node[nd])
    return f"node {nd} (block {blk}, at {np.round(state.nodes.x0[nd], 4).tolist()} m)"


def stop_rule(stops, g, last, peak, b=None):
    """(status, message) of the first of the rules ratio_tol, disp_limit,
    load_drop and past_peak that holds on the chunk's last row, or None; g
    the group of ``stops.monitor``, ``peak`` its Peak so far, b the group
    of ``stops.balance``."""
    if stops.ratio_tol is not None and last.ratio[0] < stops.ratio_tol:
        return "converged", f"unbalanced-force ratio {last.ratio[0]:.3g} < {stops.ratio_tol}"
    if g is None:
        return None
    load, disp = last.force[0, g], last.disp[0, g]
    if stops.disp_limit is not None and abs(disp) >= stops.disp_limit:
        return "displacement_limit", f"displacement {disp:.6g} m reached"
    top = peak.load if peak is not None else 0.0
    if stops.load_drop is not None and top > 0 and load < stops.load_drop * top:
        return "load_drop", f"load fell to {load / top:.3f} of the peak"
    if stops.past_peak is not None and peak is not None and top > 0:
        drop, after, at_most = stops.past_peak
        beyond = abs(disp - peak.disp)
        balanced = b is None or abs(load + last.force[0, b]) < PEAK_UNBALANCE * abs(load)
        if beyond >= at_most or (beyond >= after and balanced and load < (1.0 - drop) * top):
            return "past_peak", f"{beyond * 1e3:.3f} mm past the peak, the load at {load / top:.3f} of it"
    return None


def run(state, max_steps, stops=Stops(), controls=Controls(), chunk=200, record_every=10, progress=None):
    """``stage`` run alone: (state, Record, Ending)."""
    return drive(stage(state, max_steps, stops, controls, chunk, record_every, progress))


def stage(state, max_steps, stops=Stops(), controls=Controls(), chunk=200, record_every=10, progress=None):
    """Advances ``state`` in chunks of ``chunk`` steps under ``controls``
    (from the start of the stage: ``solver.begin``) until a rule of
    ``stops`` holds or ``max_steps`` are done: a program (module
    docstring) that returns (state, Record, Ending).
    ``progress(state, chunk_history)`` is called after every chunk."""
    t0 = time.perf_counter()
    a = state.assembly
    g = a.monitor(stops.monitor) if stops.monitor is not None else None
    if (stops.disp_limit is not None or stops.load_drop is not None or stops.balance is not None) and g is None:
        raise InputError("run.monitor", "displacement, load-drop and balance criteria need a monitor")
    balance = {g: a.monitor(stops.balance)} if stops.balance is not None else {}
    state = begin(state, controls)
    start = state.step
    peaks, rows, last = [None] * len(a.monitor_names), [], None
    status, message = "max_steps", f"reached {max_steps} steps"
    chunks = high_ratio = 0
    while state.step - start < max_steps:
        chunks += 1
        state, h = yield Advance(state, controls, min(chunk, max_steps - (state.step - start)))
        found = chunk_peaks(h, balance)
        peaks = [higher(p, c) for p, (_, c) in zip(peaks, found)]
        rows.append(decimate(h, record_every, [i for i, _ in found]))
        last = h.take(slice(-1, None))
        if progress is not None:
            progress(state, h)
        high_ratio = high_ratio + 1 if state.integrator.mode == QUASI_STATIC and last.ratio[0] > 10 else 0
        if reason := divergence(state, last, high_ratio):
            status, message = "diverged", f"{reason} at step {state.step}, starting at {diverged_where(state)}"
            break
        if chunks % 20 == 0 and (rot := max_rotation(state)) > state.integrator.rotation_limit:
            status, message = "large_displacement", (
                f"a block rotated by {rot:.3g} rad (> {state.integrator.rotation_limit}) at step {state.step}: "
                "beyond the small-displacement formulation")
            break
        if end := stop_rule(stops, g, last, peaks[g] if g is not None else None, balance.get(g)):
            status, message = end
            break
    record = Record(concat(rows, a.monitor_names), last, tuple(peaks))
    return state, record, Ending(status, message, state.step - start, time.perf_counter() - t0)
