"""The README's set-up times, each measured from a fresh clone.

    .venv/bin/python benchmarks/setup_time.py [STEP ...] [--out results/bench/setup.csv]

STEP is one or more of (all by default, in this order):
  install     `make install` in a fresh clone
  single      then the README's single run, on a cold kernel cache
  warm        then the same run again (the kernels cached)
  smoke       then, the kernel cache emptied (`make clean-cache`), the smoke run
  test        `make test` in a fresh clone of its own (install included)
  reproduce   `make reproduce` in a fresh clone of its own (install included)

Each clone is of the committed HEAD (uncommitted changes are not measured).
A step that fails stops the tool without writing.  Each measured step
replaces its row of ``--out`` (what, seconds, the step's last line of
output, the commit, the CPU and its cores); the other rows stay.
tests/test_docs_numbers.py reads the README's set-up table from it.
Measure on an otherwise idle machine."""
import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

from machine import machine

ROOT = Path(__file__).resolve().parent.parent
SINGLE = ".venv/bin/masonrydem run config/scenes/willis.yaml --out runs/ref"
STEPS = {       # step -> (the README's row, its command, a clone of its own)
    "install": ("`make install`", "make install", True),
    "single": ("a single run (above), its kernels compiled", SINGLE, False),
    "warm": ("a single run, its kernels cached", SINGLE, False),
    "smoke": ("the smoke run (above), from empty",
              "make clean-cache && .venv/bin/snakemake --cores 2 --configfile config/smoke.yaml", False),
    "test": ("`make test`", "make test", True),
    "reproduce": ("`make reproduce` (all but the accuracy study)", "make reproduce", True),
}


def measure(steps):
    commit = subprocess.run(["git", "rev-parse", "--short=7", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                            check=True).stdout.strip()
    rows, clone = [], None
    with tempfile.TemporaryDirectory() as tmp:
        for i, step in enumerate(steps):
            what, command, own = STEPS[step]
            if own or clone is None:
                clone = Path(tmp) / f"clone{i}"
                subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True)
            print(f"{step}: {command} (in {clone})", file=sys.stderr, flush=True)
            t0 = time.perf_counter()
            r = subprocess.run(command, shell=True, cwd=clone, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               env={k: v for k, v in os.environ.items() if k != "VIRTUAL_ENV"})
            seconds = time.perf_counter() - t0
            lines = [x for x in r.stdout.splitlines() if x.strip() and "is ignored" not in x]
            last = lines[-1].strip() if lines else ""
            if r.returncode:
                sys.exit(f"{step} failed (exit {r.returncode}) after {seconds:.0f} s:\n" + "\n".join(lines[-30:]))
            print(f"  {seconds:.1f} s: {last}", file=sys.stderr, flush=True)
            rows.append(dict(what=what, seconds=round(seconds, 1), last_line=last, commit=commit, **machine()))
    return pd.DataFrame(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("steps", nargs="*", default=list(STEPS), help="steps: " + ", ".join(STEPS))
    ap.add_argument("--out", type=Path, default=ROOT / "results/bench/setup.csv")
    args = ap.parse_args()
    unknown = set(args.steps) - set(STEPS)
    if unknown:
        ap.error(f"unknown step(s) {', '.join(sorted(unknown))}: the steps are {', '.join(STEPS)}")
    new = measure(args.steps)
    if args.out.exists():
        old = pd.read_csv(args.out)
        new = pd.concat([old[~old.what.isin(new.what)], new])
    order = {w: i for i, (w, _, _) in enumerate(STEPS.values())}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    new.sort_values("what", key=lambda s: s.map(order)).to_csv(args.out, index=False)
    print(new.to_string(index=False))


if __name__ == "__main__":
    main()
