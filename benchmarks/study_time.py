"""The study from empty, timed.

    .venv/bin/python benchmarks/study_time.py [--cores 2]

Removes the study's samples and per-run files (results/study/samples_*.json
and runs: the samples are drawn again and every simulation reruns), runs
`snakemake --cores N --forcerun sample study` (samples, the simulations,
collection, statistics, figures, regression, pictures) and writes
results/study/timing.csv, one row:

  wall_s           wall clock, Snakemake's start to its exit
  runs             simulations in results/study/runs.parquet
  cores            the cores given to Snakemake
  batch_runs       the runs of a simulation job (config batch.runs) ...
  lanes            ... advanced in lock-step at a time (config batch.lanes)
  core_s_per_run   wall_s x cores / runs: what a run costs the study, all
                   included (planning, start-up, the analysis)
  mean_startup_s   a run's share of its job's start-up, from the
                   interpreter's start to the first simulation (its row's
                   startup_s)
  mean_steps       mean time steps of a run
  solver_version   the rows' solver version (one for all)

Run it on an otherwise idle machine: the figure is the study's cost.
"""
import argparse
import datetime
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parent.parent


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cores", type=int, default=2)
    args = ap.parse_args()
    runs_dir = ROOT / "results" / "study" / "runs"
    if runs_dir.exists():
        shutil.rmtree(runs_dir)
    for samples in runs_dir.parent.glob("samples_*.json"):
        samples.unlink()
    snakemake = Path(sys.executable).with_name("snakemake")
    t0 = time.perf_counter()
    # forced from the samples on: with the collected tables present and up
    # to date, Snakemake would not recreate the missing per-run files
    subprocess.run([str(snakemake), "--cores", str(args.cores), "--forcerun", "sample", "--", "study"], cwd=ROOT,
                   check=True)
    wall = time.perf_counter() - t0
    runs = pd.read_parquet(ROOT / "results" / "study" / "runs.parquet")
    versions = runs["solver_version"].dropna().unique()
    import yaml
    batch = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["batch"]
    row = dict(wall_s=round(wall, 1), runs=len(runs), cores=args.cores, batch_runs=batch["runs"],
               lanes=batch["lanes"], core_s_per_run=round(wall * args.cores / len(runs), 3),
               mean_startup_s=round(float(runs["startup_s"].mean()), 3),
               mean_steps=round(float(runs["steps"].mean()), 1),
               solver_version=",".join(versions), date=datetime.date.today().isoformat())
    pd.DataFrame([row]).to_csv(ROOT / "results" / "study" / "timing.csv", index=False)
    print(pd.DataFrame([row]).to_string(index=False))


if __name__ == "__main__":
    main()
