"""Figures of the study's statistics."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from masonrydem import analysis as A  # noqa: E402
from masonrydem import figures as F  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
curves = pd.read_parquet(sm.input.curves)
stats = pd.read_csv(sm.input.statistics)
corr = pd.read_csv(sm.input.correlations)
levels = np.sort(runs.sigma_v_mpa.unique())
sv_scatter = levels[np.argmin(np.abs(levels - 0.25))]
F.running_mean(runs, sm.output.running_mean)
F.brick_share(stats, sm.output.brick_share)
F.correlation_vs_sigma(corr, sm.output.correlation)
F.scatter_deviation(runs, sv_scatter, sm.output.scatter)
F.curves_by_mode(runs, curves, [levels[0], levels[-1]], sm.output.curves)

good = runs[runs.ok]
rm = []
for (variant, sv), g in good.groupby(["variant", "sigma_v_mpa"]):
    m = A.running_mean(g.sort_values("sample").P_max_kN)
    tail = m[int(0.8 * len(m)) - 1:]
    se = g.P_max_kN.std(ddof=1) / len(g) ** 0.5 / m[-1]      # standard error of the mean, relative
    rm.append(f"{variant} {sv:g} MPa {100 * (tail.max() - tail.min()) / m[-1]:.1f} % "
              f"(standard error of the mean {100 * se:.1f} %)")
allm = stats[stats["mode"] == "all"]
share = [f"{v}: " + ", ".join(f"{r.sigma_v_mpa:g} MPa {100 * r.brick_share:.0f} %" for r in g.itertuples())
         for v, g in allm.groupby("variant")]
cva = corr[corr["mode"] == "all"]
trend = []
for v, g in cva.groupby("variant"):
    g = g.sort_values("sigma_v_mpa")
    trend.append(f"{v}: " + ", ".join(f"{n} {g[n].iloc[0]:+.2f} to {g[n].iloc[-1]:+.2f}" for n in A.INPUTS))
at = cva[(cva.variant == "nonspatial") & (cva.sigma_v_mpa == sv_scatter)]
drops = []
for (v, sv, mode), g in good[good.sigma_v_mpa.isin([levels[0], levels[-1]])].groupby(
        ["variant", "sigma_v_mpa", "failure_mode"]):
    drops.append(f"{v} {sv:g} MPa {mode} {100 * g.drop_after_peak.median():.0f} % ({len(g)} runs)")
F.write_captions(sm.input.templates, sm.output.captions, dict(
    running_mean=dict(lines="; ".join(rm)),
    brick_share=dict(lines="; ".join(share)),
    correlation_vs_sigma=dict(lines="from the lowest to the highest level, " + "; ".join(trend)),
    scatter_deviation=dict(sv=sv_scatter, n=int(at["count"].iloc[0]) if len(at) else 0,
                           lines=", ".join(f"{n} {at[n].iloc[0]:+.2f}" for n in A.INPUTS) if len(at) else "none"),
    curves_by_mode=dict(lines="; ".join(drops)),
))
