"""All simulations in one table, and all curves in another (each thinned
to the configured number of points, keeping its peak; values in single
precision).  The table has a column for the swept setting and for each
random variable (plan.analysis): the row's own where it reports it (the
precompression, the Willis study's strengths and stiffness, from the
model), else the level of the run's folder and the sample's value (its
mean over units or joints)."""
import sys
from pathlib import Path

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from masonrydem.analysis import check_one_solver, of_study  # noqa: E402
from masonrydem.quantities import to_shown  # noqa: E402
from masonrydem.results import atomic_write, downsample, read_json  # noqa: E402

spec = sm.params.analysis
level = spec["level_column"]
runs = pd.DataFrame([read_json(p) for p in sm.input.results])
if level not in runs:
    runs[level] = [sm.params.levels[Path(p).parent.parent.name] for p in sm.input.results]
print("solver", check_one_solver(runs, of_study(spec)[0]))
missing = {name: col for name, col in spec["columns"].items() if name in spec["means"] and col not in runs}
if missing:
    samples = {v: {s["sample"]: s for s in read_json(p)} for v, p in zip(sm.params.variants, sm.input.samples)}
    for name, col in missing.items():
        runs[col] = [to_shown(float(np.mean(samples[r.variant][r.sample][name])), spec["units"][name])
                     for r in runs.itertuples()]


def thinned(path):
    """The curve at about curve_points points; one that has no more (plus
    its peak) is kept whole, so thinning twice changes nothing."""
    c = pd.DataFrame(read_json(path)).astype({"step": "int64"})
    if len(c) > sm.params.curve_points + 1:
        c = c.iloc[downsample(c.displacement_mm.to_numpy(), c.load_kN.to_numpy(), sm.params.curve_points)]
    return c.astype({k: "float32" for k in ("displacement_mm", "load_kN", "ratio", "unbalance")})


curves = pd.concat([thinned(p).assign(variant=r.variant, sample=r["sample"], **{level: r[level]})
                    for p, (_, r) in zip(sm.input.curves, runs.iterrows())], ignore_index=True)
atomic_write(sm.output.runs, lambda p: runs.to_parquet(p, index=False))
atomic_write(sm.output.curves, lambda p: curves.to_parquet(p, index=False))
print(f"{len(runs)} runs, {int((~runs.ok).sum())} not ok:")
print(runs.groupby(["variant", "status"]).size().to_string())
