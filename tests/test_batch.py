"""Simulations in the lanes of a batch (dem/lockstep.py,
protocol.simulate_many, `masonrydem run --samples ... --lanes`): each run
gives the bits it gives alone, whatever its lane, the batch's width, the
runs beside it, the lanes that empty and narrow the batch, a run beside
it that raises or goes non-finite; a failed run is recorded and the
batch goes on."""
import math

import numpy as np
import pandas as pd
import pytest

from masonrydem import cli
from masonrydem.dem import lockstep
from masonrydem.dem.batch import Batch, lane_key
from masonrydem.dem import Controls, init
from masonrydem.dem.stops import Stops, stage
from masonrydem.specimen.build import build
from masonrydem.specimen.protocol import simulate, simulate_many
from masonrydem.specimen.row import curve, outcome_row
from masonrydem.scene import build_scene

WILLIS = "config/scenes/willis.yaml"
# the smoke's coarse numerics: a run in a few thousand steps
COARSE = ["numerics.cells=[2, 1, 1]", "loading.bending.rate=2e-7", "loading.bending.ramp_steps=500"]
TINY = ["geometry.courses=2", "geometry.units_per_course=2", "numerics.cells=[1, 1, 1]",
        "loading.bending.supports_x=[0.1, 0.5]", "loading.bending.loads_x=[0.25, 0.35]",
        "loading.bending.rate=2e-7", "loading.bending.ramp_steps=500"]
SHARED = ("wall_time_s", "lanes", "startup_s")      # what a batch changes: how the time was spent


def _scenes(base):
    """Runs of one mesh that differ in everything else a study varies: the
    materials of the wallette, per unit and per joint, and the level."""
    rng = np.random.default_rng(5)
    out = []
    for k, pressure in enumerate([0.0, 0.3e6, 0.0, 0.1e6, 0.5e6, 0.0, 0.2e6]):
        settings = {"materials.joints.ft": float(rng.uniform(0.2e6, 0.5e6)),
                    "materials.units.ft": float(rng.uniform(2.5e6, 5e6)),
                    "materials.units.E": float(rng.uniform(10e9, 20e9))}
        if k == 2:      # one drawn per unit and per joint
            sc = build_scene(WILLIS, base)
            settings = {"materials.per_unit.E": rng.uniform(10e9, 20e9, sc.geometry.n_units).tolist(),
                        "materials.per_joint.ft": rng.uniform(0.2e6, 0.5e6, len(sc.geometry.joints)).tolist()}
        out.append(build_scene(WILLIS, base + [f"loading.precompression.pressure={pressure}"], settings, f"s{k}"))
    return out


def _result(outcome):
    row = {k: v for k, v in outcome_row(outcome).values().items() if k not in SHARED}
    return row, {k: np.asarray(v) for k, v in curve(outcome).items()}


def _same(a, b):
    (ra, ca), (rb, cb) = a, b
    assert ra.keys() == rb.keys()
    for k in ra:
        x, y = ra[k], rb[k]
        assert x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)), (k, x, y)
    for k in ca:
        np.testing.assert_array_equal(ca[k], cb[k], err_msg=k)


def _batched(scenes, lanes):
    out = {}

    def finish(i, outcome, error):
        assert error is None, error
        out[i] = _result(outcome)
    simulate_many(scenes, finish, lanes)
    return [out[i] for i in range(len(scenes))]


def test_each_run_of_a_batch_gives_the_bits_it_gives_alone():
    """Seven runs of the Willis wallette (coarse), three lanes: lanes take
    the next run as theirs end, and the batch narrows when the last runs
    leave lanes empty; every row value and curve point is the run's alone,
    and the batch's width does not matter either."""
    scenes = _scenes(COARSE)
    alone = [_result(simulate(sc, progress=False)) for sc in scenes]
    for lanes in (3, 8):
        for a, b in zip(alone, _batched(scenes, lanes)):
            _same(a, b)


@pytest.mark.parametrize("blocks", ["rigid", "elasto-plastic"])
def test_rigid_and_zone_models_in_lanes_give_the_bits_they_give_alone(blocks):
    """The lane-by-lane kernels (rigid bodies; zones with Mohr-Coulomb) on
    their lanes' views: a tiny wallette at three levels, two lanes."""
    scenes = [build_scene(WILLIS, TINY + [f"physics.blocks={blocks}", f"loading.precompression.pressure={p}"],
                          {"materials.joints.ft": ft}, f"s{k}")
              for k, (p, ft) in enumerate([(0.0, 0.3e6), (0.2e6, 0.25e6), (0.1e6, 0.4e6)])]
    alone = [_result(simulate(sc, progress=False)) for sc in scenes]
    for a, b in zip(alone, _batched(scenes, 2)):
        _same(a, b)


def _program(specimen, state, spoil=None, after=1):
    """A run's bending stage as a program; ``spoil(state)`` after its
    ``after``-th chunk (it raises, or writes a NaN into its lane)."""
    n = 0
    stops = Stops(disp_limit=1e-4, monitor="load")
    run = stage(state, 3000, stops, Controls(ramp_steps=500), chunk=250)
    request = next(run)
    while True:
        state, h = yield request
        n += 1
        if spoil is not None and n == after:
            spoil(state)
        try:
            request = run.send((state, h))
        except StopIteration as end:
            return end.value


def _jobs(specimens, spoil_lane=None, spoil=None):
    out = {}
    jobs = []
    for i, sp in enumerate(specimens):
        def start(state, sp=sp, i=i):
            from masonrydem.dem import prescribe
            state = prescribe(state, sp.drive, sp.velocity)
            return _program(sp, state, spoil if i == spoil_lane else None)

        def finish(result, error, i=i):
            out[i] = (result, error)
        jobs.append(lockstep.Job(sp.assembly, start, finish))
    return jobs, out


def _stage_result(result):
    state, record, ending = result
    h = record.history
    return ending.status, ending.steps, h.force.tobytes(), h.disp.tobytes(), h.ratio.tobytes()


def test_a_run_that_raises_or_goes_non_finite_leaves_the_others_as_they_are():
    """Four runs in three lanes, one of which raises after its second
    chunk, or has a NaN written into its lane after its first: that one
    ends (its job is told why, or its stage says 'diverged' at that step),
    and the others' histories are bit for bit those they have alone."""
    specimens = [build(sc) for sc in _scenes(COARSE)[:4]]
    alone = {}
    for i, sp in enumerate(specimens):
        jobs, out = _jobs([sp])
        state = init(sp.assembly, sp.numerics)
        result = lockstep.drive(jobs[0].start(state))
        alone[i] = _stage_result(result)

    def boom(state):
        raise RuntimeError("boom")

    def nan(state):
        state.nodes.v[0, 0] = math.nan

    for spoil, after in ((boom, 2), (nan, 1)):
        jobs, out = _jobs(specimens, spoil_lane=1, spoil=spoil)
        batch = Batch(specimens[0].assembly, specimens[0].numerics, 3)
        lockstep.run(batch, jobs)
        for i in (0, 2, 3):
            assert out[i][1] is None and _stage_result(out[i][0]) == alone[i], (spoil.__name__, i)
        if spoil is boom:
            assert isinstance(out[1][1], RuntimeError) and out[1][0] is None
        else:
            assert out[1][1] is None and out[1][0][2].status == "diverged", out[1]
            assert "non-finite" in out[1][0][2].message and out[1][0][2].steps == 251


def test_a_batch_takes_only_runs_of_its_mesh():
    """Another mesh is refused a lane; simulate_many runs it in a batch of
    its own, each result as alone."""
    a, b = build_scene(WILLIS, COARSE), build_scene(WILLIS, COARSE + ["geometry.courses=5"])
    sa, sb = build(a), build(b)
    assert lane_key(sa.assembly, sa.numerics) != lane_key(sb.assembly, sb.numerics)
    batch = Batch(sa.assembly, sa.numerics, 2)
    with pytest.raises(ValueError, match="share one mesh"):
        batch.load(1, sb.assembly)
    scenes = [a, b, a]
    alone = [_result(simulate(sc, progress=False)) for sc in scenes]
    for x, y in zip(alone, _batched(scenes, 2)):
        _same(x, y)


def test_the_command_line_runs_a_batch_and_records_a_refused_sample(tmp_path):
    """`masonrydem run --samples F --variant V --sample ...`: each sample's
    row and curve in its own folder ({sample} in --out), its values those
    of the sample run alone; a sample the scene refuses (E = 15 Pa) is a
    row with status 'error' and its message, and the others run; --out
    without {sample} for several runs is refused before any computation."""
    import json
    samples = [{"sample": k, "f_tj": ft, "settings": {"materials.joints.ft": ft, "materials.units.E": E},
                "inputs": {"f_tj": "materials.joints.ft"}}
               for k, (ft, E) in enumerate([(0.3e6, 15e9), (0.25e6, 15.0), (0.4e6, 12e9)])]
    path = tmp_path / "samples.json"
    path.write_text(json.dumps(samples))
    argv = ["run", WILLIS, *sum([["--set", s] for s in COARSE], []), "--samples", str(path), "--variant", "v",
            "--sample", "0", "--sample", "1", "--sample", "2", "--lanes", "2", "--format", "json", "--quiet"]
    assert cli.main(argv + ["--out", str(tmp_path / "one")]) == 2
    assert cli.main(argv + ["--out", str(tmp_path / "s{sample}"), "--exit-zero"]) == 0
    rows = {k: json.loads((tmp_path / f"s{k}" / "result.json").read_text()) for k in range(3)}
    assert rows[1]["status"] == "error" and "materials.units.E" in rows[1]["message"] and rows[1]["f_tj_mpa"] == 0.25
    for k in (0, 2):
        sc = build_scene(WILLIS, COARSE, samples[k]["settings"], f"v:s{k}")
        row, run_curve = _result(simulate(sc, progress=False))
        got = {c: v for c, v in rows[k].items() if c not in SHARED}
        assert got["ok"] and got["P_max_kN"] == row["P_max_kN"] and got["steps"] == row["steps"]
        assert (got["variant"], got["sample"], got["f_tj_mpa"]) == ("v", k, samples[k]["settings"]["materials.joints.ft"] / 1e6)
        written = json.loads((tmp_path / f"s{k}" / "curve.json").read_text())
        for c, x in run_curve.items():
            np.testing.assert_array_equal(np.asarray(written[c]), x, err_msg=c)
