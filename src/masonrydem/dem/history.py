"""Histories with named columns, and the peak tracker: small pure
functions over them.

A peak is the largest load reached near equilibrium, once the velocity
ramp is over: a load carried while the model is far from equilibrium is
inertia, not strength.  Near equilibrium means that the load's own
unbalance |F + F_b| / |F| is below PEAK_UNBALANCE, F_b the reaction that
balances it in a static state (the supports against the load lines), or,
for a monitor without one, that the model's unbalanced-force ratio is.
docs/formulation.md, section 10, gives the measurements behind the rule.
"""
from typing import NamedTuple

import numpy as np

from . import kernels as K

# a load counts as a peak only with at most this fraction of it unbalanced
PEAK_UNBALANCE = 0.01


class History(NamedTuple):
    """Rows of steps: the step number, the unbalanced-force ratio, the
    kinetic energy, per monitor (``monitors``: their names, in group
    order) its force (the reaction of its constraint) and its mean
    displacement, and whether the prescribed velocities were at full
    speed (the velocity ramp over)."""
    step: np.ndarray            # (n,) int64
    ratio: np.ndarray           # (n,)
    kinetic_energy: np.ndarray  # (n,)
    force: np.ndarray           # (n, monitors)
    disp: np.ndarray            # (n, monitors)
    loading: np.ndarray         # (n,) bool
    monitors: tuple

    @property
    def rows(self):
        return self.step.shape[0]

    def group(self, name):
        """The column of the monitor named ``name``."""
        return self.monitors.index(name)

    def force_of(self, name):
        return self.force[:, self.group(name)]

    def disp_of(self, name):
        return self.disp[:, self.group(name)]

    def take(self, index):
        """The rows ``index`` (a mask, indices or a slice)."""
        return self._replace(**{f: getattr(self, f)[index] for f in _COLUMNS})


_COLUMNS = ("step", "ratio", "kinetic_energy", "force", "disp", "loading")


def from_kernel(hist, loading, monitors):
    """The History of the step kernel's rows (kernels.layout H_*)."""
    g = len(monitors)
    return History(step=hist[:, K.H_STEP].astype(np.int64), ratio=hist[:, K.H_RATIO], kinetic_energy=hist[:, K.H_KE],
                   force=hist[:, [K.h_force(i) for i in range(g)]], disp=hist[:, [K.h_disp(i) for i in range(g)]],
                   loading=loading, monitors=tuple(monitors))


def concat(histories, monitors):
    """The rows of ``histories`` one after the other."""
    if not histories:
        g = len(monitors)
        return History(np.zeros(0, np.int64), np.zeros(0), np.zeros(0), np.zeros((0, g)), np.zeros((0, g)),
                       np.zeros(0, bool), tuple(monitors))
    return histories[0]._replace(**{f: np.concatenate([getattr(h, f) for h in histories]) for f in _COLUMNS})


def unbalance(history, g, balance=None):
    """Per row, the unbalanced fraction of monitor group g's load:
    |F_g + F_b| / |F_g| with its balancing group ``balance``, else the
    model's unbalanced-force ratio."""
    if balance is None:
        return history.ratio
    f = history.force[:, g]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.abs(f + history.force[:, balance]) / np.abs(f)


class Peak(NamedTuple):
    """The largest load of a monitor near equilibrium, where it was reached."""
    load: float
    disp: float
    step: int
    ratio: float
    unbalance: float


def chunk_peaks(history, balance):
    """Per monitor group, the row of the chunk ``history`` that carries its
    largest load near equilibrium and after the velocity ramp (None where
    there is none), and that row's Peak.  ``balance``: group -> the group
    whose reaction balances it."""
    out = []
    for g in range(len(history.monitors)):
        u = unbalance(history, g, balance.get(g))
        balanced = (u < PEAK_UNBALANCE) & history.loading
        if not balanced.any():
            out.append((None, None))
            continue
        i = int(np.argmax(np.where(balanced, history.force[:, g], -np.inf)))
        out.append((i, Peak(float(history.force[i, g]), float(history.disp[i, g]), int(history.step[i]),
                            float(history.ratio[i]), float(u[i]))))
    return out


def higher(peak, candidate):
    """The higher of a peak so far (None: none yet) and a candidate."""
    if candidate is None or (peak is not None and not candidate.load > peak.load):
        return peak
    return candidate


def decimate(history, every, also=()):
    """The rows kept of a chunk: every ``every``-th step, the chunk's last
    row, and the rows ``also`` (each monitor's peak of the chunk, so that
    the exact peak is a recorded row)."""
    keep = history.step % every == 0
    if history.rows:
        keep[-1] = True
    for i in also:
        if i is not None:
            keep[i] = True
    return history.take(keep)
