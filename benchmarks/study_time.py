"""Wall time of the study's simulations, from Snakemake's own logs.

    python benchmarks/study_time.py .snakemake/log/<the study's sittings>.snakemake.log

For every finished `simulate` job in the logs: its time in Snakemake (from
the job's start line to its "Finished" line, one-second resolution) and the
run's own wall time inside the solver (wall_time_s of its result row).  The
difference is the per-job start-up overhead (scheduling, interpreter,
imports, reading the scene and samples, writing the outputs).

Prints per log the span of the Snakemake run and the jobs it finished, then
the totals: jobs, summed Snakemake wall time of the logs, mean job time,
mean overhead.  Only jobs whose result file is still the one they wrote
count (its modification time lies within the job).  A study run in
several sittings (Snakemake resumes only the missing jobs) is timed by the
sum of its logs' spans; give only logs of study runs (a log of other rules
would add their time to the span).
"""
import os
import re
import sys
from datetime import datetime, timedelta

import pandas as pd

STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ \d\d:\d\d:\d\d \d{4})\]$")
OUTPUT = re.compile(r"^\s+output: (\S+\.parquet),")
JOBID = re.compile(r"^\s+jobid: (\d+)$")
ONE_S = timedelta(seconds=1)
FINISHED = re.compile(r"^Finished jobid: (\d+) \(Rule: simulate\)$")


def parse(path):
    """(first stamp, last stamp, {jobid: (start, end, result file)}) of one log."""
    stamp = first = None
    started, jobs, rule, out = {}, {}, None, None
    for line in open(path):
        line = line.rstrip("\n")
        if m := STAMP.match(line):
            stamp = datetime.strptime(" ".join(m.group(1).split()), "%a %b %d %H:%M:%S %Y")
            first = first or stamp
        elif line.endswith("rule simulate:"):
            rule, out = "simulate", None
        elif rule and (m := OUTPUT.match(line)):
            out = m.group(1)
        elif rule and (m := JOBID.match(line)):
            started[int(m.group(1))] = (stamp, out)
            rule = None
        elif m := FINISHED.match(line):
            t0, out = started[int(m.group(1))]
            jobs[int(m.group(1))] = (t0, stamp, out)
    return first, stamp, jobs


def main(paths):
    rows, span = [], 0.0
    for path in paths:
        first, last, jobs = parse(path)
        if not jobs:
            continue
        span += (last - first).total_seconds()
        print(f"{path}: {first} to {last}, {len(jobs)} simulations finished")
        for t0, t1, out in jobs.values():
            if not os.path.exists(out) or not t0 <= datetime.fromtimestamp(os.path.getmtime(out)) <= t1 + ONE_S:
                continue      # gone, or rerun since (a later log counts it)
            wall = pd.read_parquet(out, columns=["wall_time_s"])["wall_time_s"].iloc[0]
            rows.append(((t1 - t0).total_seconds(), wall))
    if not rows:
        sys.exit("no finished simulate jobs in the logs")
    d = pd.DataFrame(rows, columns=["job_s", "run_s"])
    print(f"simulations: {len(d)}; Snakemake wall time of the logs: {span / 3600:.2f} h "
          f"({span / len(d):.1f} s per simulation on the cores given)")
    print(f"mean job time {d.job_s.mean():.1f} s, mean run time {d.run_s.mean():.1f} s, "
          f"per-job overhead {(d.job_s - d.run_s).mean():.2f} s")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
