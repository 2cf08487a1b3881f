"""Statistics and correlations of the study's runs."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import INPUTS, correlation_band, correlations, increase, input_spread, statistics  # noqa: E402,E501
from masonrydem.figures import write_captions  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
st = statistics(runs)
st.to_csv(sm.output.statistics, index=False, float_format="%.4g")
corr = correlations(runs)
corr.to_csv(sm.output.correlations, index=False, float_format="%.4g")
levels = sorted(runs.sigma_v_mpa.unique())
inc = increase(st, levels[0], levels[-1])
inc.assign(sigma_from=levels[0], sigma_to=levels[-1]).to_csv(sm.output.increase, index=False, float_format="%.4g")
print(st.to_string())

n_corr = int(corr.loc[corr["mode"] == "all", "count"].max())
noise = f"+-{correlation_band(n_corr):.2f} for n = {n_corr}" if n_corr > 2 else "undefined for so few runs"


def spread(variant):
    cov = input_spread(runs, variant)
    return ", ".join(f"{n} {v:.3f}" for n, v in cov.items()) if cov else "none run"


bad = runs[~runs.ok]
allm = st[st["mode"] == "all"]
stat_lines = [f"- {r.variant}, {r.sigma_v_mpa:g} MPa: mean **{r.P_max_mean_kN:.2f} kN** "
              f"({r.strength_mean_mpa:.3f} MPa), COV **{r.P_max_cov:.3f}**, {r.count} runs, "
              f"{100 * r.brick_share:.0f} % brick failures" for r in allm.itertuples()]
corr_lines = []
for r in corr[corr["mode"] == "all"].itertuples():
    vals = {n: getattr(r, n) for n in INPUTS}
    top = max(vals, key=lambda n: abs(vals[n]) if pd.notna(vals[n]) else -1)
    corr_lines.append(f"- {r.variant}, {r.sigma_v_mpa:g} MPa: {top} ({vals[top]:+.2f}); "
                      + ", ".join(f"{n} {v:+.2f}" for n, v in vals.items()))
write_captions(sm.input.templates, sm.output.captions, dict(
    statistics=dict(excluded=len(bad), total=len(runs), lines="\n".join(stat_lines),
                    excluded_detail=(" (" + ", ".join(f"{k}: {v}" for k, v in bad.status.value_counts().items())
                                     + ")") if len(bad) else ""),
    correlations=dict(lines="\n".join(corr_lines), noise=noise, field_spread=spread("spatial"),
                      point_spread=spread("nonspatial")),
    increase=dict(lines="; ".join(f"{r.variant} {r.mode} **{100 * r.increase:+.0f} %**" for r in inc.dropna().itertuples())
                  + f" (from {levels[0]:g} to {levels[-1]:g} MPa)"),
))
