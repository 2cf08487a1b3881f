"""Prediction equations (Lasso, 5-fold CV) per failure mode on the
non-spatial runs; the lower-of-two prediction against the design rules."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from masonrydem import analysis as A  # noqa: E402
from masonrydem import figures as F  # noqa: E402
from masonrydem.sampling import STUDY_VARIABLES  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
ns = runs[runs.ok & (runs.variant == "nonspatial")]
fits, rows = {}, []
for mode in ("joint", "brick"):
    g = ns[ns.failure_mode == mode]
    if len(g) < 7:   # nested 5-fold CV: each inner fit needs 5 runs of the outer 4/5
        rows.append(dict(mode=mode, n=len(g), equation="too few runs to fit"))
        continue
    eq = A.fit_equation(g.f_tu_mpa, g.f_tj_mpa, g.sigma_v_mpa, g.strength_mpa, seed=sm.params.seed)
    fits[mode] = (eq, g.strength_mpa.to_numpy())
    rows.append(dict(mode=mode, n=eq["n"], alpha=eq["alpha"], mape_pct=eq["mape"], cv_mape_pct=eq["cv_mape"],
                     intercept=eq["intercept"], **eq["coef"], equation=A.equation_text(eq)))
pd.DataFrame(rows).to_csv(sm.output.equations, index=False, float_format="%.5g")
F.predicted_vs_simulated(fits, sm.output.predicted)

# lower of two at the mean properties, with a band of one standard deviation
# of the prediction over the sampled properties (f_tu, f_tj of the 100
# non-spatial samples), beside the simulated mean +- 1 SD per level
mean = {v.name: v.mean for v in STUDY_VARIABLES}
f_tu, f_tj = mean["f_tu"] / 1e6, mean["f_tj"] / 1e6
levels = np.linspace(0.0, max(runs.sigma_v_mpa.max(), 0.5), 51)
pred = band = np.full_like(levels, np.nan)
resid_sd = np.nan
if fits:
    eqs = {m: e for m, (e, _) in fits.items()}
    joint, brick = eqs.get("joint", eqs.get("brick")), eqs.get("brick", eqs.get("joint"))
    pred, _ = A.lower_of_two(joint, brick, np.full_like(levels, f_tu), np.full_like(levels, f_tj), levels)
    props = runs[runs.variant == "nonspatial"].drop_duplicates("sample")
    band = A.prediction_scatter(joint, brick, props.f_tu_mpa, props.f_tj_mpa, levels)
    fit_all, _ = A.lower_of_two(joint, brick, ns.f_tu_mpa, ns.f_tj_mpa, ns.sigma_v_mpa)
    resid_sd = float(np.std(ns.strength_mpa - fit_all, ddof=1))
# model quantities for the rules: c_j = 1.2 f_tj; overlap l_o = half a
# modelled unit (120 mm), h_b = modelled unit height (75 mm); AS3700 f_mt
# from f_tj (flexural bond ~ tensile bond of the joint), f_ut from f_tu
lg = A.lourenco_gaetani(1.2 * f_tj, f_tu, 0.120, 0.075)
as_stepped, as_line = A.as3700(f_tj, f_tu, levels)
sim = ns.groupby("sigma_v_mpa").strength_mpa.agg(["mean", "std"])
F.design_comparison(levels, pred, band, lg, as_stepped, as_line,
                    (sim.index.to_numpy(), sim["mean"].to_numpy(), sim["std"].to_numpy()), sm.output.design)
pd.DataFrame(dict(sigma_v_mpa=levels, prediction=pred, band_sd=band, lg_stepped=lg[0], lg_brick=lg[1],
                  as3700_stepped=as_stepped, as3700_line=as_line)).to_csv(
    sm.output.design_table, index=False, float_format="%.5g")
print(pd.DataFrame(rows).to_string())

eq_lines = [f"- {r['mode']} failure ({r['n']} runs): " + (
    f"**{r['equation']}**, MAPE **{r['mape_pct']:.1f} %** on the runs it was fitted to, "
    f"**{r['cv_mape_pct']:.1f} %** out of fold; alpha {r['alpha']:.3g}" if "alpha" in r else r["equation"])
    for r in rows]
design_lines = []
for sv in sim.index:
    at = lambda y: float(np.interp(sv, levels, y))  # noqa: E731
    design_lines.append(f"- {sv:g} MPa: simulated **{sim.loc[sv, 'mean']:.3f} +- {sim.loc[sv, 'std']:.3f} MPa**, "
                        f"predicted **{at(pred):.3f} +- {at(band):.3f} MPa**; Lourenco-Gaetani stepped {lg[0]:.3f} / "
                        f"brick {lg[1]:.3f} MPa; AS3700 stepped {at(as_stepped):.3f} / line {at(as_line):.3f} MPa")
F.write_captions(sm.input.templates, sm.output.captions, dict(
    equations=dict(lines="\n".join(eq_lines)),
    design_comparison=dict(f_tu=f_tu, f_tj=f_tj, resid=resid_sd, lines="\n".join(design_lines)),
))
