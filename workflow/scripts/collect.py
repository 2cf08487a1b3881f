"""All simulations in one table, and all curves in another (each thinned
to the configured number of points, keeping its peak; values in single
precision).  Each run's row carries the study's variables by their names
(the samples file gives them); the swept setting's column is the row's
own where it reports it (the precompression), else the level of the
run's folder."""
import sys
from pathlib import Path

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from masonrydem.analysis.statistics import check_one_solver, lower_bounds, of_study  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.scene import PRECOMPRESSION, build_scene  # noqa: E402
from masonrydem.specimen.protocol import DROP_WINDOW  # noqa: E402
from masonrydem.specimen.row import atomic_write, downsample, read_json  # noqa: E402

spec = sm.params.analysis
level = spec["level_column"]
runs = lower_bounds(pd.DataFrame([read_json(p) for p in sm.input.results]),
                    build_scene(plan.study(sm.config).scene).loading.drive.rate, DROP_WINDOW)
if level not in runs:
    runs[level] = [sm.params.levels[Path(p).parent.parent.name] for p in sm.input.results]
if spec["setting"] == PRECOMPRESSION and level != "sigma_v_mpa" and "sigma_v_mpa" in runs:
    # the precompression is the study's level: one column, by the study's name (p_mpa)
    assert ((runs.sigma_v_mpa - runs[level]).abs() <= 1e-9 * runs[level].abs().max()).all()
    runs = runs.drop(columns="sigma_v_mpa")
print("solver", check_one_solver(runs, of_study(spec)[0]))
missing = [col for name, col in spec["columns"].items() if name in spec["means"] and col not in runs]
if missing:
    raise ValueError(f"the runs do not report the study's inputs {missing}: rows of another study or an older "
                     "version; rerun them")


def thinned(path):
    """The curve's columns at about curve_points points; one that has no
    more (plus its peak) is kept whole, so thinning twice changes nothing."""
    c = {k: np.asarray(v) for k, v in read_json(path).items()}
    if len(c["step"]) > sm.params.curve_points + 1:
        keep = downsample(c["displacement_mm"], c["load_kN"], sm.params.curve_points)
        c = {k: v[keep] for k, v in c.items()}
    return c


# every curve's columns joined (one table built, not one a run), in single
# precision, each point with its run's variant, sample and level
parts = [thinned(p) for p in sm.input.curves]
columns = {k: np.concatenate([c[k] for c in parts]) for k in parts[0]}
columns["step"] = columns["step"].astype("int64")
columns.update({k: columns[k].astype("float32") for k in ("displacement_mm", "load_kN", "ratio", "unbalance")})
lengths = [len(c["step"]) for c in parts]
columns.update({k: np.repeat(runs[k].to_numpy(), lengths) for k in ("variant", "sample", level)})
curves = pd.DataFrame(columns)
atomic_write(sm.output.runs, lambda p: runs.to_parquet(p, index=False))
atomic_write(sm.output.curves, lambda p: curves.to_parquet(p, index=False))
print(f"{len(runs)} runs, {int((~runs.ok).sum())} not ok:")
print(runs.groupby(["variant", "status"]).size().to_string())
