"""Small specimens for the verification tests."""
import numpy as np

from masonrydem.dem import Elastic, Model
from masonrydem.dem.history import concat
from masonrydem.dem import Numerics, init, prescribe
from masonrydem.dem.stops import Stops, run

# the quasi-static integration these tests were written at (local damping 0.8)
QS = Numerics(damping=0.8, safety=0.9)



def two_blocks(joint_law, props, size=0.1, height=0.05, cells=(1, 1, 1), E=1e12):
    """Two stiff elastic blocks stacked along z, touching at z = height."""
    m = Model()
    mat = Elastic(E=E, nu=0.2)
    lower = m.add_box([0, 0, 0], [size, size, height], cells, mat)
    upper = m.add_box([0, 0, height], [size, size, 2 * height], cells, mat)
    m.set_joints(joint_law, props)
    return m, lower, upper


def block_nodes(m, blk):
    return np.arange(blk.node0, blk.node0 + blk.n_nodes)


def work(history, group=0):
    """Work of the monitored load, int P du (trapezoidal rule)."""
    P = history.force[:, group]
    u = history.disp[:, group]
    return float(np.sum(0.5 * (P[1:] + P[:-1]) * np.diff(u)))


def pull_joint(props, rate=2e-9, law="coupled_softening", max_steps=200_000):
    """Direct tension of one joint under displacement control: the lower
    block is fixed, every node of the upper block moves up at ``rate`` per
    step.  Returns (final state, history, area)."""
    m, lower, upper = two_blocks(law, props)
    m.fix(block_nodes(m, lower))
    up = block_nodes(m, upper)
    m.fix(up, dofs=(0, 1, 2), velocity=(0.0, 0.0, rate))
    m.add_monitor("pull", up, 2)
    state = init(m.build(), QS)
    wu = 2 * props.GI / props.ft
    state, rec, _ = run(state, max_steps, Stops(disp_limit=1.2 * wu + props.ft / props.kn, monitor="pull"),
                        record_every=1)
    return state, rec.history, 0.01


def shear_joint(props, sigma, rate=2e-9, law="coupled_softening", travel=None, max_steps=400_000):
    """Direct shear of one joint at constant normal (compressive) stress
    ``sigma``: lower block fixed; every node of the upper block moves along x
    at ``rate`` per step, is held in y and free in z; a pressure sigma acts
    on the top face.  Returns (final state, history, area)."""
    m, lower, upper = two_blocks(law, props)
    m.fix(block_nodes(m, lower))
    up = block_nodes(m, upper)
    m.fix(up, dofs=(0, 1), velocity=(rate, 0.0))
    if sigma:
        m.add_pressure(2, 0.1, +1, ((-1, 1), (-1, 1)), sigma)
    m.add_monitor("shear", up, 0)
    state = init(m.build(), QS)
    histories = []
    if sigma:                       # precompress first, then shear
        state = prescribe(state, (up, 0), 0.0)
        state, rec, _ = run(state, 50_000, Stops(ratio_tol=1e-8), record_every=1)
        histories.append(rec.history)
        state = prescribe(state, (up, 0), rate)
    su = 2 * props.GII / props.c
    travel = travel or 1.5 * su + props.c / props.ks
    state, rec, _ = run(state, max_steps, Stops(disp_limit=travel, monitor="shear"), record_every=1)
    histories.append(rec.history)
    return state, concat(histories, state.assembly.monitor_names), 0.01
