"""Simulations as programs, advanced alone or in the lanes of a batch.

A program is a generator: it yields an ``Advance`` (a state, the
controls of its chunk, its number of steps), is sent back the advanced
state and the chunk's History, and returns its result (stops.stage is
one; specimen/protocol.py chains stages into a simulation).  ``drive``
runs one program alone, on a batch of one (solver.advance).  ``run``
advances the programs of many simulations of one mesh in the lanes of a
Batch (solver.py), in lock-step: every kernel call advances every lane by
the steps left in the shortest lane's chunk, and a lane whose chunk is
done is sent its history and set to its program's next chunk.  A lane
whose program has ended takes the next job; with none left it is
emptied.

Every lane's values are those of its simulation run alone, bit for bit:
the kernels compute each lane by the same operations as a run alone
(kernels/layout.py), and a chunk split over several kernel calls takes
the velocity factor of each step from the chunk's start as a run alone
does.  A program that raises ends its job (``Job.finish`` is told why),
and the others go on.

A simulation is one thread: the cells' matrix products (BLAS) run on one
thread while a program runs (threadpoolctl), as many simulations as cores
running side by side (a batch's larger products would otherwise take
every core, and fight the other simulations for them).
"""
from typing import NamedTuple

import numpy as np
import scipy.linalg.cython_blas  # noqa: F401  (the BLAS the kernels call, loaded so that threadpoolctl sees it)
from threadpoolctl import threadpool_limits

from .batch import width
from .solver import advance, advanced, started


class Advance(NamedTuple):
    """A program's request: advance ``state`` ``n`` steps under ``controls``."""
    state: object
    controls: object
    n: int


class Job(NamedTuple):
    """A simulation for a lane: its model, ``start(state) -> program`` for
    its state at rest, and ``finish(result, error)``, called with the
    program's result (error None) or, if it raised, the exception (result
    None) while the lane still holds its state."""
    assembly: object
    start: object
    finish: object


def drive(program):
    """The result of ``program`` run alone (its states a batch of one)."""
    with threadpool_limits(1, user_api="blas"):
        try:
            request = next(program)
            while True:
                request = program.send(advance(request.state, request.controls, request.n))
        except StopIteration as end:
            return end.value


class _Lane:
    """A lane's job, its program, the chunk it is in and the rows so far."""

    def __init__(self, job, program):
        self.job, self.program = job, program

    def take(self, request, batch):
        """The program's next chunk, set up in the lane."""
        self.state, self.controls, self.n = started(request.state), request.controls, request.n
        self.rows = np.empty((self.n, batch.width))
        self.done = 0
        batch.set_lane(self.state, self.controls)


def run(batch, jobs):
    """Runs ``jobs`` (an iterable of Job, each a model that ``batch.fits``)
    in the lanes of ``batch`` until every one has finished.  When the jobs
    are all started and the busy lanes fit a narrower batch (batch.width),
    the batch narrows to them: an empty lane costs as much as a busy one."""
    with threadpool_limits(1, user_api="blas"):
        _Lockstep(batch, jobs).run()


class _Lockstep:
    def __init__(self, batch, jobs):
        self.batch, self.queue, self.started_all = batch, iter(jobs), False
        self.lanes = [None] * batch.lanes

    def fill(self, b):
        """Lane b takes the next job that starts, or is emptied."""
        for job in self.queue:
            lane = _Lane(job, None)
            try:
                lane.program = job.start(self.batch.load(b, job.assembly))
                request = next(lane.program)
            except StopIteration as end:
                job.finish(end.value, None)
                continue
            except Exception as e:     # nothing lost: the job says why
                job.finish(None, e)
                continue
            lane.take(request, self.batch)
            self.lanes[b] = lane
            return
        self.started_all = True
        self.lanes[b] = None
        self.batch.clear(b)

    def narrow(self):
        busy = [b for b, lane in enumerate(self.lanes) if lane is not None]
        self.batch = self.batch.narrowed(busy)
        self.lanes = [self.lanes[b] for b in busy] + [None] * (self.batch.lanes - len(busy))
        for b, lane in enumerate(self.lanes[:len(busy)]):
            lane.state = lane.state._replace(batch=self.batch, lane=b)

    def run(self):
        for b in range(self.batch.lanes):
            self.fill(b)
        while any(self.lanes):
            busy = sum(lane is not None for lane in self.lanes)
            if self.started_all and width(busy) < self.batch.lanes:
                self.narrow()
            m = min(lane.n - lane.done for lane in self.lanes if lane is not None)
            done, rows, finite = self.batch.advance(m)
            for b, lane in enumerate(self.lanes):
                if lane is None:
                    continue
                lane.rows[lane.done:lane.done + done] = rows[:, :, b]
                lane.done += done
                if lane.done < lane.n and finite[b]:
                    self.batch.ctl.k0[b] = lane.done
                    continue
                try:
                    request = lane.program.send(advanced(lane.state, lane.controls, lane.rows[:lane.done],
                                                         bool(finite[b])))
                except StopIteration as end:
                    lane.job.finish(end.value, None)
                    self.fill(b)
                    continue
                except Exception as e:
                    lane.job.finish(None, e)
                    self.fill(b)
                    continue
                lane.take(request, self.batch)
