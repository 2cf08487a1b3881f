"""Where a study run's time goes: built, set up, stepped, judged, written.

    .venv/bin/python benchmarks/run_cost.py [--runs 32] [--lanes 8] [--out results/bench/run_cost.csv]

The first ``--runs`` committed non-spatial samples of the study at 0.15 MPa,
run as a study job runs them, in one process with warm kernels: one after
another, each a batch of one, and then all in one batch of ``--lanes``
lanes (the workflow's, config/config.yaml, by default).  Writes ``--out``,
a row per part, a column per way: the seconds a run spends in the part
(build: the scene's model assembled; load: a lane set up, the masses
and, once per batch, the step kernel found in numba's cache; steps: the
step kernel; stages: the rest, the stop rules, peaks and histories between
chunks; written: the classification, the row, the curve and the run's
files; total), and a row of the mean steps; and the machine.  One thread
(the cells' BLAS products too).  docs/speed.md's table of a run's cost
is this file (tests/test_docs_numbers.py)."""
import argparse
import os
import sys
import tempfile
import time
from collections import defaultdict
from dataclasses import replace
from pathlib import Path

import pandas as pd
import yaml

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from machine import machine  # noqa: E402

from masonrydem.dem import batch as B  # noqa: E402
from masonrydem.specimen import protocol, row as R  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402
from masonrydem.study.file import load_study  # noqa: E402

SPENT = defaultdict(float)


def timed(owner, name, part):
    """owner.name, its time added to SPENT[part]."""
    f = getattr(owner, name)

    def g(*args, **kw):
        t0 = time.perf_counter()
        try:
            return f(*args, **kw)
        finally:
            SPENT[part] += time.perf_counter() - t0
    setattr(owner, name, g)


def scenes(n, level=0.15e6):
    study = load_study(ROOT / "config/studies/willis.yaml")
    out = []
    for i, sample in enumerate(replace(study, scene=str(ROOT / study.scene)).draw("nonspatial").records()[:n]):
        out.append((build_scene(ROOT / study.scene, [f"loading.precompression.pressure={level}"], sample["settings"],
                                f"nonspatial:s{i}"), sample))
    return out


def run(runs, lanes, out):
    steps = []

    def finish(i, outcome, error):
        assert error is None, error
        row = R.outcome_row(outcome, variant="nonspatial", sample=i, inputs=runs[i][1]["inputs"])
        R.write(Path(out) / f"s{i}", row, R.curve(outcome), "json")
        steps.append(row.steps)
    SPENT.clear()
    t0 = time.perf_counter()
    if lanes:
        protocol.simulate_many([sc for sc, _ in runs], finish, lanes)
    else:
        for i, (sc, _) in enumerate(runs):
            protocol.simulate_many([sc], lambda _, outcome, error, i=i: finish(i, outcome, error), 1)
    total = time.perf_counter() - t0
    parts = {k: v / len(runs) for k, v in SPENT.items()}
    parts["stages"] = (total - sum(SPENT.values())) / len(runs)      # the rest: the programs' Python
    return dict(parts, total=total / len(runs), mean_steps=sum(steps) / len(steps))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=32)
    ap.add_argument("--lanes", type=int, default=yaml.safe_load((ROOT / "config/config.yaml").read_text())["batch"]["lanes"])
    ap.add_argument("--out", type=Path, default=ROOT / "results/bench/run_cost.csv")
    args = ap.parse_args()
    timed(protocol, "build", "build")
    timed(B.Batch, "load", "load")
    timed(B.Batch, "__init__", "load")
    timed(B.Batch, "advance", "steps")
    timed(R, "outcome_row", "written")
    timed(R, "curve", "written")
    timed(R, "write", "written")
    runs = scenes(args.runs)
    with tempfile.TemporaryDirectory() as tmp:
        run(runs[:2], 2, tmp)                       # kernels loaded, caches warm
        ways = {"alone": run(runs, 0, tmp), f"batch of {args.lanes}": run(runs, args.lanes, tmp)}
    t = pd.DataFrame(ways).loc[["build", "load", "steps", "stages", "written", "total", "mean_steps"]].round(4)
    t = t.rename_axis("part").reset_index().assign(runs=len(runs), lanes=args.lanes, **machine())
    args.out.parent.mkdir(parents=True, exist_ok=True)
    t.to_csv(args.out, index=False)
    print(t.to_string(index=False))


if __name__ == "__main__":
    main()
