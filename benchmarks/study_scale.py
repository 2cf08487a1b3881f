"""What a run costs the study at 1,000 runs and at 10,000.

    .venv/bin/python benchmarks/study_scale.py [--samples 100 1000] [--cores 2]

For each N of ``--samples``: the study of config/config.yaml with N samples
(2 variants x N x 5 levels runs) from empty, into a folder of its own
(scale/N, removed first; ignored by git), by the workflow as a user runs it
(`snakemake --cores C study`, then `snakemake --report`).  Writes
results/bench/study_scale.csv, a row per N:

  runs, wall_s     the runs, and Snakemake's start to its exit
  planning_s       the start to the first job (Snakemake's start, the plan)
  batches_s        the first simulation job's start to the last one's end
  collect_s        the collection of the runs (rule collect)
  analysis_s       collect's end to the last job's end: statistics,
                   equations, Sobol indices, figures, pictures, tables
  tail_s           the last job's end to Snakemake's exit
  report_s         `snakemake --report` of the study
  peak_rss_mb      the largest process's peak resident memory (Snakemake's
                   own included), from the kernel's account of the tree
  core_s_per_run   wall_s x cores_used (the cores given) / runs

(job times from Snakemake's log, to the second), and the machine; and
results/bench/study_scale_sobol.csv: the total Sobol indices of the
non-spatial variant, all runs, with their 95 % intervals at each N.
docs/speed.md's table of the study at scale is these files
(tests/test_docs_numbers.py).  Run it on an otherwise idle machine.
"""
import argparse
import datetime
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
from machine import machine  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ \d\d:\d\d:\d\d \d{4})\]$")
START = re.compile(r"^(?:local)?rule (\w+):$")
END = re.compile(r"^Finished jobid: \d+ \(Rule: (\w+)\)$")


def job_times(log):
    """[(rule, seconds since the epoch)] of each job's start and end in a
    Snakemake log."""
    out, at = [], None
    for line in log.splitlines():
        line = line.strip()
        if m := STAMP.match(line):
            at = datetime.datetime.strptime(m.group(1), "%a %b %d %H:%M:%S %Y").timestamp()
        elif (m := START.match(line) or END.match(line)) and at is not None:
            out.append((m.group(1), at))
    return out


def run(args, log):
    """Run ``args`` in the repository, its output to ``log``: (its start,
    its wall s, the tree's peak resident memory in MB, the output)."""
    t0 = time.time()
    with open(log, "w") as f:
        p = subprocess.Popen(args, cwd=ROOT, stdout=f, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(p.pid, 0)
    wall = time.time() - t0
    text = Path(log).read_text()
    if status != 0:
        sys.exit(f"{' '.join(map(str, args))} failed: {log}\n{text[-2000:]}")
    return t0, wall, usage.ru_maxrss / 1024, text


def study(samples, cores):
    """One N: the study from empty, its report, and the row."""
    out = ROOT / "scale" / str(samples)
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    config = out / "workflow.yaml"
    config.write_text(f"results: scale/{samples}\nstudy: {{samples: {samples}}}\n")
    snakemake = Path(sys.executable).with_name("snakemake")
    configs = ["--configfile", "config/config.yaml", str(config.relative_to(ROOT))]
    t0, wall, rss, log = run([snakemake, "--cores", str(cores), *configs, "--", "study"], out / "study.log")
    jobs = job_times(log)
    sims = [t for r, t in jobs if r.startswith("simulate")]
    collect = [t for r, t in jobs if r == "collect"]
    last = max(t for _, t in jobs)
    _, report, rss_report, _ = run([snakemake, "--report", f"scale/{samples}/report.zip", *configs, "--", "study"],
                                    out / "report.log")
    runs = pd.read_parquet(out / "study" / "runs.parquet")
    row = dict(samples=samples, runs=len(runs), ok=int(runs.ok.sum()), wall_s=round(wall, 1),
               planning_s=round(min(t for _, t in jobs) - t0, 1), batches_s=round(max(sims) - min(sims), 1),
               collect_s=round(max(collect) - min(collect), 1), analysis_s=round(last - max(collect), 1),
               tail_s=round(t0 + wall - last, 1), report_s=round(report, 1), peak_rss_mb=round(max(rss, rss_report)),
               core_s_per_run=round(wall * cores / len(runs), 3), **machine(), cores_used=cores,
               date=datetime.date.today().isoformat())
    print(row, flush=True)
    sobol = pd.read_csv(out / "study" / "sensitivity.csv")
    sobol = sobol[(sobol["mode"] == "all") & (sobol.variant == "nonspatial")].dropna(subset=["ST"])
    return row, sobol.assign(samples=samples)[["samples", "sigma_v_mpa", "input", "runs", "cv_r2", "ST", "ST_lo",
                                                  "ST_hi"]]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, nargs="+", default=[100, 1000])
    ap.add_argument("--cores", type=int, default=2)
    args = ap.parse_args()
    rows, sobol = zip(*(study(n, args.cores) for n in args.samples))
    bench = ROOT / "results" / "bench"
    pd.DataFrame(rows).to_csv(bench / "study_scale.csv", index=False)
    pd.concat(sobol).to_csv(bench / "study_scale_sobol.csv", index=False, float_format="%.4g")
    print(pd.DataFrame(rows).to_string(index=False))


if __name__ == "__main__":
    main()
