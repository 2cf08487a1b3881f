"""3-D pictures of typical study runs.  Per variant and failure mode: the
level where the mode is most frequent, and there the run nearest the
median P_max of the mode; it is run again with its final state (the rerun
must repeat the recorded P_max exactly: runs are bit-for-bit repeatable)."""
import sys

import numba

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)
sys.stderr = sys.stdout = open(sm.log[0], "w")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

from masonrydem import figures  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402
from masonrydem.study import run_sample  # noqa: E402
from masonrydem.viz import picture_damage, state_blocks  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
base = load_scene(sm.input.scene, sm.params.overrides)
lines = []
for (variant, mode), path in zip(sm.params.pictures, sm.output.pictures):
    group = runs[(runs.variant == variant) & (runs.failure_mode == mode) & runs.ok]
    if group.empty:
        fig, ax = plt.subplots(figsize=(8, 2))
        ax.axis("off")
        ax.text(0.5, 0.5, f"{variant}: no run failed in the {mode} mode", ha="center", va="center")
        fig.savefig(path)
        lines.append(f"- {variant}, {mode} failure: no run")
        continue
    sv = group.sigma_v_mpa.value_counts().sort_index().idxmax()
    at = group[group.sigma_v_mpa == sv]
    pick = at.iloc[(at.P_max_kN - at.P_max_kN.median()).abs().argmin()]
    samples = pd.read_parquet(sm.input.samples[sm.params.variants.index(variant)])
    row, _, specimen, solver = run_sample(base, samples, variant, sv, pick["sample"])
    same = row["P_max_kN"] == pick.P_max_kN and row["failure_mode"] == pick.failure_mode
    if not same:
        raise RuntimeError(f"{variant} s{pick['sample']} at {sv} MPa: the rerun gives P_max {row['P_max_kN']} kN "
                           f"({row['failure_mode']}), the study recorded {pick.P_max_kN} kN ({pick.failure_mode})")
    title = f"{variant} sample {pick['sample']}, sigma_v = {sv:g} MPa: P_max {pick.P_max_kN:.2f} kN, {mode} failure"
    picture_damage(state_blocks(specimen, solver), path, title=title)
    lines.append(f"- {variant}, {mode} failure: sample {pick['sample']} at {sv:g} MPa (the level with most "
                 f"{mode} failures, {len(at)} of them, median P_max {at.P_max_kN.median():.2f} kN): "
                 f"P_max **{pick.P_max_kN:.2f} kN**, repeated exactly by the rerun")
    print(lines[-1])
figures.write_caption(sm.input.template, sm.output.caption, lines="\n".join(lines))
