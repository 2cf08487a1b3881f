"""Vertical bending's numerical defaults against converged references
(docs/accuracy.md, "Vertical bending"): the committed vertical scene
(config/scenes/solid_vertical.yaml) at three bond strengths and two
precompressions, each run at candidate settings and at a reference
(finer bed-joint sub-contacts and cells, a tenth of the rate), and the
reference itself checked against a finer one at two of the cases.

    python tools/vertical_accuracy.py [results/accuracy/vertical.csv]

Writes one row per run: the case, the candidate, its settings, P_max, the
error against the case's reference, status, steps and run time (two runs
side by side on two cores), and the solver's version.  Every setting not
named here is the scene's (and so the schema's vertical defaults for the
ones the scene leaves out)."""
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pandas as pd

from masonrydem.scene import build_scene
from masonrydem.scene.files import read_scene
from masonrydem.specimen import outcome_row, simulate

SCENE = "config/scenes/solid_vertical.yaml"
CASES = [(p, ft) for p in (0.0, 0.25e6) for ft in (0.1e6, 0.2e6, 0.4e6)]
HEAD = [1, 2, 1]
# name -> (bed joints' sub-contact refinement, rate m/step, cells per unit)
CANDIDATES = {
    "horizontal defaults": ([1, 1, 1], 7.5e-8, [4, 3, 2]),
    "bed refined, horizontal rate": ([1, 2, 1], 7.5e-8, [4, 3, 2]),
    "vertical defaults": ([1, 2, 1], 2.5e-8, [4, 3, 2]),
    "bed refined, 1e-8": ([1, 2, 1], 1e-8, [4, 3, 2]),
    "reference": ([1, 4, 1], 2.5e-9, [4, 3, 4]),
}
FINER = ("finer reference", ([1, 8, 1], 1e-9, [4, 3, 6]))
FINER_CASES = [(0.0, 0.1e6), (0.25e6, 0.4e6)]


def run(job):
    name, (bed, rate, cells), (p, ft) = job
    raw = read_scene(SCENE)
    raw["materials"]["joints"]["ft"] = ft
    raw["loading"]["precompression"]["pressure"] = p
    raw["loading"]["bending"]["rate"] = rate
    raw["numerics"] = {"subcontact_refine": {"head": HEAD, "bed": bed}, "cells": cells}
    t0 = time.perf_counter()
    row = outcome_row(simulate(build_scene(raw), progress=False))
    return dict(pressure_mpa=p / 1e6, f_tj_mpa=ft / 1e6, candidate=name, bed_refine="x".join(map(str, bed)),
                rate=rate, cells="x".join(map(str, cells)), P_max_kN=row.P_max_kN, status=row.status,
                steps=row.steps, run_s=round(time.perf_counter() - t0, 1), solver_version=row.solver_version)


def main(out="results/accuracy/vertical.csv"):
    jobs = [(name, how, case) for case in CASES for name, how in CANDIDATES.items()]
    jobs += [(FINER[0], FINER[1], case) for case in FINER_CASES]
    with ProcessPoolExecutor(2) as pool:
        rows = pd.DataFrame(list(pool.map(run, jobs)))
    ref = rows[rows.candidate == "reference"].set_index(["pressure_mpa", "f_tj_mpa"]).P_max_kN
    key = pd.MultiIndex.from_frame(rows[["pressure_mpa", "f_tj_mpa"]])
    rows.insert(rows.columns.get_loc("status"), "error", rows.P_max_kN.to_numpy() / ref.loc[key].to_numpy() - 1.0)
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    rows.to_csv(out, index=False)
    summary = rows.groupby("candidate", sort=False).error.agg(lambda e: e.abs().max())
    print(json.dumps({k: f"{v:.2%}" for k, v in summary.items()}, indent=1))


if __name__ == "__main__":
    main(*sys.argv[1:])
