"""Checkpoint of an unfinished study run, so that it survives a lost machine.

The per-run files results/study/runs/** are git-ignored (about 40 kB a run:
40 MB for the study).  This folder holds what they contain in compact form:
rows.parquet (every finished run's row, exact) and curves.parquet (each curve
thinned to study.curve_points points in single precision, exactly as
`collect` thins it, so the collected results come out identical).

    python results/study/checkpoint/checkpoint.py save      # refresh it
    python results/study/checkpoint/checkpoint.py restore   # on a fresh clone

restore writes the per-run files back and marks them up to date with
`snakemake --touch` (a fresh clone's mtimes would otherwise make Snakemake
redo the sampling and so every run); then `snakemake --cores 2 study` runs
only the missing simulations.  Delete this folder once the study is complete.
"""
import subprocess
import sys
from pathlib import Path

import pandas as pd
import yaml

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "src"))
from masonrydem.runner import atomic_write, downsample  # noqa: E402

HERE = Path(__file__).resolve().parent
RUNS = ROOT / "results/study/runs"
KEYS = ["variant", "sigma_v_mpa", "sample"]


def curve_points():
    return yaml.safe_load((ROOT / "config/config.yaml").read_text())["study"]["curve_points"]


def save():
    rows, curves = [], []
    n = curve_points()
    for p in sorted(RUNS.glob("*/sv*/s*[0-9].parquet")):
        cp = p.with_name(p.stem + "_curve.parquet")
        if not cp.exists():
            continue
        rows.append(pd.read_parquet(p))
        c = pd.read_parquet(cp)
        c = c.iloc[downsample(c.displacement_mm.to_numpy(), c.load_kN.to_numpy(), n)]
        curves.append(c.astype({k: "float32" for k in ("displacement_mm", "load_kN", "ratio")}))
    rows = pd.concat(rows, ignore_index=True)
    atomic_write(HERE / "rows.parquet", lambda q: rows.to_parquet(q, index=False))
    atomic_write(HERE / "curves.parquet", lambda q: pd.concat(curves, ignore_index=True).to_parquet(q, index=False))
    print(len(rows))


def restore():
    rows = pd.read_parquet(HERE / "rows.parquet")
    curves = pd.read_parquet(HERE / "curves.parquet")
    targets = []
    for (variant, sv, sample), c in curves.groupby(KEYS, sort=False):
        d = RUNS / variant / f"sv{sv}"
        d.mkdir(parents=True, exist_ok=True)
        r = rows[(rows.variant == variant) & (rows.sigma_v_mpa == sv) & (rows["sample"] == sample)]
        assert len(r) == 1, (variant, sv, sample)
        r.to_parquet(d / f"s{sample}.parquet", index=False)
        c.to_parquet(d / f"s{sample}_curve.parquet", index=False)
        targets += [str((d / f"s{sample}{x}.parquet").relative_to(ROOT)) for x in ("", "_curve")]
    subprocess.run([str(ROOT / ".venv/bin/snakemake"), "--cores", "1", "--touch", *targets], cwd=ROOT, check=True)
    print(f"restored {len(rows)} runs")


if __name__ == "__main__":
    {"save": save, "restore": restore}[sys.argv[1]]()
