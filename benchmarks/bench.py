"""Solver speed on a wallette-sized model (24 bricks), one thread, for
every unit model, and the start-up of a study job.

    .venv/bin/python benchmarks/bench.py [--tiny] [--out results/bench/bench.json] [--only bootstrap]

Prints one JSON line and writes it to ``--out`` (not with ``--tiny``):
the machine (cpu, cores) and, per unit model (under "models"):
  ns_per_tet_step         zone kernel time / (tetrahedra x steps)
  ns_per_cell_step        elastic cells computed as linear (elements.py):
                          cell kernel time / (cells x steps); for the
                          zone model the time of its 10 tetrahedra per cell
  ns_per_subcontact_step  joint kernel time / (sub-contacts x steps)
  steps_per_s             whole time steps per second (zones or cells,
                          joints, bearings, node update, histories)
  lanes                   per number of lanes S of a batch (1, 8 and 32,
                          each lane a copy of the state): the kernels'
                          ns per item, lane and step (ns_per_*_step), and
                          step_us, a whole step of the batch per lane (us)
and, at the top level, the elasto-plastic model's figures (the source
paper's model), its figures in brick failure, and
  kernel_load_s           a fresh process: time of the solver's set-up
                          (solver.init, which loads the step kernel) and
                          first time step of a small model once the kernels
                          are cached (import of the package not included;
                          reported apart)
  import_s                a fresh process: `import masonrydem`
  job                     a study job (`python -m masonrydem.cli run
                          --samples ...`) on a small wallette: its own
                          start-up (interpreter start to the simulation's
                          start) and its wall time
  levers                  the speed levers of docs/dev/performance-log.md, each on top of those before
                          it: the mean wall time and steps of 12 study
                          runs (6 committed samples at 0 and 0.5 MPa), the
                          time against 'before' and the change of P_max
  bootstrap               the regression's bootstrap of the equations on
                          the committed runs: ms per resample on one
                          process and on two, and whether both agree
``--only bootstrap`` measures that part alone and replaces it in ``--out``
(the rest as measured before).  The kernels are timed on realistic
states: the wallette loaded past its peak (joint failure: joints
softening), and a strong-joint wallette past its peak (brick failure:
zones or crack interfaces cracking).  ``--tiny``:
the same on a wallette of 2 x 2 units of one cell each (two for the
potential-crack units), a few hundred steps (tests/test_bench.py runs it,
so that the benchmark cannot break unnoticed).  docs/speed.md's table of
the lanes is results/bench/bench.json's potential-crack model
(tests/test_docs_numbers.py).
"""
import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")      # one thread: the cells' products too

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))

from masonrydem.dem import kernels as K  # noqa: E402
from masonrydem.dem.kernels.cells import cell_forces  # noqa: E402
from masonrydem.dem.kernels.joints import contact_forces  # noqa: E402
from masonrydem.dem.kernels import lanes  # noqa: E402
from masonrydem.dem.kernels.step import lane_nodes, lane_zones  # noqa: E402
from masonrydem.dem.kernels.zones import zone_forces  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402
from masonrydem.dem import Controls, init, prescribe, zone_damage  # noqa: E402
from masonrydem.specimen.build import build  # noqa: E402
from masonrydem.dem.stops import run  # noqa: E402
from machine import machine  # noqa: E402

SCENE = "config/scenes/willis.yaml"
TINY = ["geometry.courses=2", "geometry.units_per_course=2", "numerics.cells=[1, 1, 1]",
        "loading.bending.supports_x=[0.1, 0.5]", "loading.bending.loads_x=[0.25, 0.35]"]
# unit model -> its overrides (wallette, tiny wallette): the source paper's
# elasto-plastic zones, elastic units as zones and as linear cells and
# rigid units, all on 5x2x2 cells per unit; the potential-crack units on
# the study's mesh (the scene's own settings)
MESH = ["numerics.cells=[5, 2, 2]"]
EP, EL = ["physics.blocks=elasto-plastic"], ["physics.blocks=elastic"]
MODELS = {
    "elasto-plastic": ([*EP, *MESH], EP),
    "elastic-zones": ([*EL, "numerics.elastic_element=zones", *MESH], [*EL, "numerics.elastic_element=zones"]),
    "elastic-tet10": ([*EL, "numerics.elastic_element=tet10", *MESH], [*EL, "numerics.elastic_element=tet10"]),
    "elastic-hex8i": ([*EL, "numerics.elastic_element=hex8i", *MESH], [*EL, "numerics.elastic_element=hex8i"]),
    "potential-crack": ([], ["numerics.cells=[2, 1, 1]"]),
    "rigid": (["physics.blocks=rigid", *MESH], ["physics.blocks=rigid"]),
}
STRONG = ["materials.joints.ft=1.0e6", "materials.joints.GI=30.0"]

FRESH = """
import time, sys
t0 = time.perf_counter()
import masonrydem
from masonrydem.scene import build_scene
from masonrydem.dem import Controls, advance, init
from masonrydem.specimen.build import build
t1 = time.perf_counter()
sp = build(build_scene("config/scenes/willis.yaml", ["geometry.courses=2", "numerics.cells=[1, 1, 1]"]))
t2 = time.perf_counter()
advance(init(sp.assembly, sp.numerics), Controls(), 1)
t3 = time.perf_counter()
print(t1 - t0, t3 - t2)
"""


def fresh_process_times(repeat=3):
    out = []
    for _ in range(repeat):
        r = subprocess.run([sys.executable, "-c", FRESH], capture_output=True, text=True, check=True)
        out.append([float(x) for x in r.stdout.split()])
    return np.median(np.array(out), axis=0)


def _kernels(zlaw, jlaw, nl):
    """The zone, cell and joint kernels of these laws, as the step kernel
    compiles them (the law ids and lanes are constants of the wrappers),
    over every lane of a batch (nl lanes: one, the kernels of one run;
    more, those of kernels/lanes.py), each run ``n`` times per call: a
    call from Python costs tens of microseconds (its containers are typed
    and unboxed), which the loop amortises.  The zones run lane by lane,
    as in a step."""
    @njit(error_model="numpy")
    def zones(n, dt, nodes, z, scratch):
        for _ in range(n):
            for b in range(nl):
                zone_forces(zlaw, dt, lane_nodes(nodes, b), lane_zones(z, b), scratch)

    if nl == 1:
        @njit(error_model="numpy")
        def cells(n, nodes, c, scratch):
            one = _one(nodes, c)
            for _ in range(n):
                cell_forces(one[0], one[1], scratch)

        @njit(error_model="numpy")
        def joints(n, dt, nodes, bodies, sc):
            one = _one(nodes, None)
            for _ in range(n):
                contact_forces(jlaw, 0, 0, dt[0], one[0], bodies, sc)
    else:
        @njit(error_model="numpy")
        def cells(n, nodes, c, scratch):
            for _ in range(n):
                lanes.cell_forces(nodes, c, nl)

        @njit(error_model="numpy")
        def joints(n, dt, nodes, bodies, sc):
            for _ in range(n):
                lanes.contact_forces(jlaw, dt, nodes, sc, nl)

    return zones, cells, joints


@njit(error_model="numpy")
def _one(nodes, cells):
    """A batch of one's nodes and cells as one run's arrays."""
    n = nodes.u.shape[0]
    one = K.Nodes(nodes.x0, nodes.u.reshape(n, 3), nodes.v.reshape(n, 3), nodes.f.reshape(n, 3),
                  nodes.mass.reshape(n, 3), nodes.mgrav.reshape(n), nodes.fixed, nodes.vpres.reshape(n, 3),
                  nodes.fext.reshape(n, 3))
    if cells is None:
        return one, None
    return one, K.Cells(cells.nodes, cells.kind, cells.scale.reshape(cells.scale.shape[0]), cells.K)


def best_of(fn, n, repeat=5):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        best = min(best, time.perf_counter() - t0)
    return best / n


LANES = (1, 8, 32)


def kernel_times(overrides, steps=6000, ramp=2000, lanes=LANES):
    """Loads the wallette of SCENE (with ``overrides``) for ``steps`` steps,
    then times whole steps as a stage runs them and, in batches of each
    number of ``lanes`` (every lane a copy of that state), the zone, cell
    and joint kernels and whole steps of the batch: per item, lane and
    step (ns) and per lane and step (us)."""
    sp = build(build_scene(SCENE, overrides))
    s = prescribe(init(sp.assembly, sp.numerics), sp.drive, [0.0, 5e-8, 0.0])
    s, _, _ = run(s, steps, controls=Controls(ramp_steps=ramp), chunk=500)
    nt, nc, nsc = s.zones.tets.shape[0], s.assembly.cells.nodes.shape[0], s.joints.area.shape[0]
    # whole steps as a stage runs them: 500 steps, their histories and peaks
    t_step = best_of(lambda: run(s, 500, chunk=500), 1, repeat=6) / 500
    out = dict(steps_per_s=round(1.0 / t_step, 1), tetrahedra=int(nt), cells=int(nc), subcontacts=int(nsc),
               damaged_subcontacts=int((s.joints.state[:, K.JS_D] > 0).sum()),
               cracked_zones=int((zone_damage(s) > 0).sum()) if nt else 0)
    per = {}
    for S in lanes:
        zone_kernel, cell_kernel, joint_kernel = _kernels(s.assembly.zlaw, s.assembly.jlaw, S)
        b = s.batch.narrowed([s.lane] * S)        # S copies of the loaded state
        c, scratch = b.containers, b.scratch
        nodes = c["nodes"]._replace(f=np.zeros_like(c["nodes"].f))
        dt = np.full(S, 1.0)
        t = dict(step_us=round(best_of(lambda: b.advance(500), 1, repeat=4) / (500 * S) * 1e6, 2))
        if nt:
            zone_kernel(1, 1.0, nodes, c["zones"], scratch)
            t_zone = best_of(lambda: zone_kernel(50, 1.0, nodes, c["zones"], scratch), 1) / 50
            t["ns_per_tet_step"] = round(t_zone / (nt * S) * 1e9, 1)
        if nc:
            cell_kernel(1, nodes, c["cells"], scratch)
            t_cell = best_of(lambda: cell_kernel(200, nodes, c["cells"], scratch), 1) / 200
            t["ns_per_cell_step"] = round(t_cell / (nc * S) * 1e9, 1)
        if nsc:
            joint_kernel(1, dt, nodes, c["bodies"], c["joints"])
            reps = max(20, 2000 // S)
            t_joint = best_of(lambda: joint_kernel(reps, dt, nodes, c["bodies"], c["joints"]), 1) / reps
            t["ns_per_subcontact_step"] = round(t_joint / (nsc * S) * 1e9, 1)
        per[S] = t
    one = per[lanes[0]]
    out.update({k: v for k, v in one.items() if k != "step_us"})
    if nt:
        out["ns_per_cell_step"] = round(10 * one["ns_per_tet_step"], 1)
    out["lanes"] = per
    return out


def job_times(tiny):
    """A study job as the workflow runs it (`python -m masonrydem.cli run
    --samples ...`: one sample of the study, one thread), on the tiny
    wallette or on the 2-course wallette: its own start-up (startup_s, from
    the interpreter's start to the simulation's start) and the job's wall
    time."""
    import tempfile
    from masonrydem.specimen.row import write_json
    from masonrydem.study.file import load_study
    from dataclasses import replace
    size = TINY if tiny else ["geometry.courses=2", "numerics.cells=[1, 1, 1]"]
    study = replace(load_study("config/studies/willis.yaml"), samples=2, seed=1)
    with tempfile.TemporaryDirectory() as tmp:
        write_json(f"{tmp}/samples.json", study.draw("nonspatial").records())
        cmd = [sys.executable, "-m", "masonrydem.cli", "run", SCENE, "--samples", f"{tmp}/samples.json", "--variant",
               "nonspatial", "--sample", "0", "--out", tmp, "--format", "json", "--exit-zero",
               *(x for o in size for x in ("--set", o))]
        best = None
        for _ in range(1 if tiny else 3):
            t0 = time.perf_counter()
            subprocess.run(cmd, capture_output=True, check=True)
            wall = time.perf_counter() - t0
            with open(f"{tmp}/result.json") as f:
                row = json.load(f)
            if best is None or row["startup_s"] < best["startup_s"]:
                best = dict(startup_s=round(row["startup_s"], 3), wall_s=round(wall, 3), steps=row["steps"])
    return best


# the speed levers (docs/dev/performance-log.md), each on top of the ones before it (a study run as the
# workflow runs it, in one process: committed samples, the study's numerics)
PAST_PEAK = "loading.bending.past_peak={drop: 0.05, after: 1.0e-4, at_most: 2.0e-4}"
LEVERS = {"before": ["numerics.cells=[6, 3, 2]"],
          "past_peak": ["numerics.cells=[6, 3, 2]", PAST_PEAK],
          "cells_4x3x2": ["numerics.cells=[4, 3, 2]", PAST_PEAK]}


def lever_times(n=6, levels=(0.0, 0.5)):
    """Per lever (LEVERS): the mean wall time and steps of the study's runs
    of the first ``n`` committed non-spatial samples at ``levels``, and
    their P_max's mean change against 'before' (its runs first, so that all
    run with warm kernels)."""
    from gate import W, run_one
    from masonrydem.study.file import load_study
    samples = load_study("config/studies/willis.yaml").draw("nonspatial").records()[:n]
    run_one(W, TINY + ["numerics.cells=[1, 1, 1]"], samples[0], "nonspatial")     # kernels loaded
    out, base = {}, None
    for name, overrides in LEVERS.items():
        rows = []
        for sample in samples:
            for sv in levels:
                t0 = time.perf_counter()
                row, _ = run_one(W, overrides + [f"loading.precompression.pressure={sv * 1e6}"], sample,
                                 "nonspatial")
                rows.append((time.perf_counter() - t0, row["steps"], row["P_max_kN"], row["failure_mode"]))
        wall, steps, p, mode = (np.array(x) for x in zip(*rows))
        base = (wall, steps, p, mode) if base is None else base
        out[name] = dict(run_s=round(float(wall.mean()), 3), steps=int(steps.mean()),
                         time_ratio=round(float(wall.sum() / base[0].sum()), 3),
                         P_max_change_pct=round(float(100 * np.mean(p / base[2] - 1)), 3),
                         P_max_max_change_pct=round(float(100 * np.max(np.abs(p / base[2] - 1))), 3),
                         same_mode=int((mode == base[3]).sum()), runs=len(rows))
    return out


def bootstrap_times(tiny):
    """The regression's bootstrap of the equations (equations.equation_intervals)
    on the committed study's ok non-spatial runs: its time on one process and
    on two, per resample, and whether the two give the same intervals."""
    import pandas as pd
    from masonrydem.analysis import equations as E
    from masonrydem.study.file import load_study
    study = load_study("config/studies/willis.yaml")
    runs = pd.read_parquet("results/study/runs.parquet")
    ns = runs[runs.ok & (runs.variant == study.regression_variant)]
    if tiny:
        ns = ns[ns["sample"] < 30]
    n = 24 if tiny else 200
    out, tables = {}, []
    for jobs in (1, 2):
        t0 = time.perf_counter()
        tables.append(E.equation_intervals(ns, study.features, study.columns(), resamples=n, seed=0, jobs=jobs,
                                           block=12 if tiny else 100))
        out[f"jobs{jobs}_ms_per_resample"] = round(1e3 * (time.perf_counter() - t0) / n, 1)
    out.update(resamples=n, same=bool(tables[0].equals(tables[1])))
    return out


PARTS = {"bootstrap": bootstrap_times}      # the parts --only measures alone


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tiny", action="store_true", help="a wallette of 2 x 2 units, a few hundred steps")
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent.parent / "results/bench/bench.json")
    ap.add_argument("--only", choices=sorted(PARTS), help="measure this part alone and replace it in --out")
    args = ap.parse_args()
    if args.only:
        out = json.loads(args.out.read_text())
        out[args.only] = PARTS[args.only](args.tiny)
        print(json.dumps(out[args.only]))
        if not args.tiny:
            args.out.write_text(json.dumps(out, indent=1) + "\n")
        return
    out = measure(args.tiny)
    print(json.dumps(out))
    if not args.tiny:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(out, indent=1) + "\n")


def measure(tiny):
    fresh_process_times(1)          # make sure the cache is warm
    import_s, load_s = fresh_process_times(1 if tiny else 3)
    steps, ramp = (600, 200) if tiny else (6000, 2000)
    models = {}
    for name, (full, small) in MODELS.items():
        # every width compiles its kernels (half a minute): the tiny run
        # batches the first model's lanes, the others run alone
        lanes = LANES if not tiny else LANES[:2] if not models else LANES[:1]
        base = small + TINY if tiny else full
        models[name] = kernel_times(base, steps, ramp, lanes)
        if name in ("elasto-plastic", "potential-crack"):
            # strong joints: the bricks crack (brick failure), so the plastic path runs
            brick = kernel_times(base + STRONG, int(1.5 * steps), ramp, lanes)
            models[name]["brick_failure"] = {k: v for k, v in brick.items()
                                             if k.startswith(("ns_", "steps_", "cracked"))}
    out = dict(machine(), **models["elasto-plastic"])
    out.update(kernel_load_s=round(load_s, 3), import_s=round(import_s, 3), job=job_times(tiny), models=models,
               bootstrap=bootstrap_times(tiny))
    if not tiny:
        out["levers"] = lever_times()
    return out


if __name__ == "__main__":
    main()
