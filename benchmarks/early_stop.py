"""The lever 'stop once the peak is certain': the committed study's
runs again with ``loading.bending.past_peak``, against their committed
rows (results/study/runs.parquet, same solver arithmetic).

For every run it prints whether P_max, the displacement at the peak and
drop_after_peak are the committed ones to the last digit, whether the
failure mode is the same, and the steps saved; then the totals.  A run
whose mode differs is listed with its evidence, both ways.

    python benchmarks/early_stop.py --samples 20 --levels 0 0.5 --jobs 2
    python benchmarks/early_stop.py --all --jobs 2           # the 1000 runs
"""
import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import yaml  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
from gate import W, run_one  # noqa: E402
from masonrydem.study.file import load_study  # noqa: E402

RULE = "loading.bending.past_peak={drop: 0.05, after: 1.0e-4, at_most: 2.0e-4}"
SAME = ("P_max_kN", "disp_at_peak_mm", "drop_after_peak", "peak_step")
EVIDENCE = ("failure_mode", "cracked_units", "unit_crack_fraction", "broken_joints", "classification")


def _one(job):
    variant, sv, sample, overrides = job
    t0 = time.perf_counter()
    row, _ = run_one(W, overrides, sample, variant)
    row["wall_s"] = time.perf_counter() - t0
    return variant, sv, row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=20, help="the first N samples of each variant")
    ap.add_argument("--levels", type=float, nargs="+", default=[0.0, 0.5], help="precompressions (MPa)")
    ap.add_argument("--all", action="store_true", help="every committed run")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--rule", default=RULE)
    ap.add_argument("--out", help="write the per-run table (CSV) here")
    args = ap.parse_args()
    with open("config/config.yaml") as f:
        numerics = yaml.safe_load(f)["numerics"]
    committed = pd.read_parquet("results/study/runs.parquet").set_index(["variant", "sigma_v_mpa", "sample"])
    levels = sorted(committed.index.get_level_values(1).unique()) if args.all else args.levels
    n = int(committed.index.get_level_values(2).max()) + 1 if args.all else args.samples
    jobs, study = [], load_study("config/studies/willis.yaml")
    for variant in ("nonspatial", "spatial"):
        for s in study.draw(variant).records()[:n]:
            for sv in levels:
                jobs.append((variant, sv, s, numerics + [f"loading.precompression.pressure={sv * 1e6}", args.rule]))
    rows, t0 = [], time.perf_counter()
    with ProcessPoolExecutor(args.jobs) as pool:
        for k, (variant, sv, row) in enumerate(pool.map(_one, jobs, chunksize=1)):
            old = committed.loc[(variant, sv, row["sample"])]
            same = all(row[c] == old[c] or (np.isnan(row[c]) and np.isnan(old[c])) for c in SAME)
            rows.append(dict(variant=variant, sv=sv, sample=row["sample"], same_peak=same,
                             same_mode=row["failure_mode"] == old.failure_mode, steps=row["steps"],
                             old_steps=int(old.steps), status=row["status"], old_status=old.status, wall_s=row["wall_s"],
                             **{f"new_{c}": row[c] for c in EVIDENCE}, **{f"old_{c}": old[c] for c in EVIDENCE}))
            r = rows[-1]
            print(f"{k + 1:4d}/{len(jobs)} {variant:10s} {sv:5g} s{r['sample']:<3d} peak {'same' if same else 'DIFFERS'}"
                  f" mode {row['failure_mode']:5s}{'' if r['same_mode'] else ' (was ' + old.failure_mode + ')'} "
                  f"steps {r['steps']:6d} (was {r['old_steps']:6d}) {row['status']}", flush=True)
    t = pd.DataFrame(rows)
    if args.out:
        t.to_csv(args.out, index=False)
    ok = t[t.old_status.isin(["load_drop", "displacement_limit"])]
    print(f"\n{len(t)} runs in {time.perf_counter() - t0:.0f} s on {args.jobs} processes; rule {args.rule}")
    print(f"peak (P_max, its displacement and step, drop_after_peak) identical: {int(t.same_peak.sum())} of {len(t)}")
    print(f"failure mode the same: {int(t.same_mode.sum())} of {len(t)}")
    print(f"steps: {t.steps.mean():.0f} a run, was {t.old_steps.mean():.0f} ({100 * (t.steps.sum() / t.old_steps.sum() - 1):+.1f} %);"
          f" the committed ok runs: {ok.steps.mean():.0f}, was {ok.old_steps.mean():.0f}")
    for mode, g in t.groupby("old_failure_mode"):
        print(f"  {mode} failures ({len(g)}): {g.steps.mean():.0f} steps, was {g.old_steps.mean():.0f}")
    bad = t[~t.same_mode | ~t.same_peak]
    if len(bad):
        print("\nruns that differ:")
        print(bad.drop(columns=["wall_s"]).to_string(index=False))


if __name__ == "__main__":
    main()
