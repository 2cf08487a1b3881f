"""Prediction equations (Lasso, 5-fold CV) per failure mode on the
non-spatial runs; the lower-of-two prediction checked run by run and
against the design rules."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from masonrydem import analysis as A  # noqa: E402
from masonrydem import figures as F  # noqa: E402
from masonrydem.sampling import STUDY_VARIABLES  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
ns = runs[runs.ok & (runs.variant == "nonspatial")]
fits, rows = {}, []
for mode in ("joint", "brick"):
    g = ns[ns.failure_mode == mode]
    if g["sample"].nunique() < A.MIN_GROUPS:
        rows.append(dict(mode=mode, n=len(g), equation=f"too few runs to fit ({g['sample'].nunique()} samples, "
                                                          f"the nested 5-fold CV needs {A.MIN_GROUPS})"))
        continue
    eq = A.fit_equation(g.f_tu_mpa, g.f_tj_mpa, g.sigma_v_mpa, g.strength_mpa, g["sample"])
    fits[mode] = (eq, g.strength_mpa.to_numpy())
    rows.append(dict(mode=mode, n=eq["n"], alpha=eq["alpha"], mape_pct=eq["mape"], cv_mape_pct=eq["cv_mape"],
                     intercept=eq["intercept"], **eq["coef"], equation=A.equation_text(eq)))

# the predictor itself: the lower of the two equations, its mode that of the
# lower one, on every non-spatial run (with one equation it stands for both)
resid_sd = np.nan
lines = []
if fits:
    eqs = {m: e for m, (e, _) in fits.items()}
    joint, brick = eqs.get("joint", eqs.get("brick")), eqs.get("brick", eqs.get("joint"))
    low, low_mode = A.lower_of_two(joint, brick, ns.f_tu_mpa, ns.f_tj_mpa, ns.sigma_v_mpa)
    resid_sd = float(np.std(ns.strength_mpa - low, ddof=1))
    hit = float(np.mean(low_mode == ns.failure_mode.to_numpy()))
    rows.append(dict(mode="lower of two", n=len(ns), mape_pct=A.mape(ns.strength_mpa, low), mode_agreement=hit,
                     residual_sd_mpa=resid_sd,
                     equation="min(joint, brick)" if len(fits) == 2 else f"the {next(iter(fits))} equation alone"))
pd.DataFrame(rows).to_csv(sm.output.equations, index=False, float_format="%.5g")
F.predicted_vs_simulated(fits, sm.output.predicted)

# lower of two at the mean properties against sigma_v, with a band of one
# standard deviation: the scatter of the prediction over the sampled
# properties (f_tu, f_tj of the non-spatial samples) and the residual
# scatter the equations leave (phi_j, E_b and the misfit), combined
mean = {v.name: v.mean for v in STUDY_VARIABLES}
f_tu, f_tj = mean["f_tu"] / 1e6, mean["f_tj"] / 1e6
levels = np.linspace(0.0, max(runs.sigma_v_mpa.max(), 0.5), 51)
pred = band = prop_sd = prop_mean = np.full_like(levels, np.nan)
if fits:
    pred, _ = A.lower_of_two(joint, brick, np.full_like(levels, f_tu), np.full_like(levels, f_tj), levels)
    props = ns.drop_duplicates("sample")            # the properties of every sample with an ok run
    prop_mean, prop_sd = A.prediction_over_samples(joint, brick, props.f_tu_mpa, props.f_tj_mpa, levels)
    band = np.sqrt(prop_sd ** 2 + resid_sd ** 2)
# model quantities for the rules, from the scene: c_j = c_ratio f_tj; the
# overlap l_o = bond offset x modelled unit length, h_b = modelled unit
# height (unit + joint); AS3700 f_mt from f_tj (flexural bond ~ tensile bond
# of the joint), f_ut from f_tu
scene = load_scene(sm.input.scene)
geo, joints = scene["geometry"], scene["materials"]["joints"]
l_o = geo["bond_offset"] * (geo["unit"]["length"] + geo["joint_thickness"])
h_b = geo["unit"]["height"] + geo["joint_thickness"]
lg = A.lourenco_gaetani(joints["c_ratio"] * f_tj, f_tu, l_o, h_b)
as_stepped, as_line = A.as3700(f_tj, f_tu, levels)
sim = ns.groupby("sigma_v_mpa").strength_mpa.agg(["mean", "std"])
F.design_comparison(levels, pred, band, prop_mean, lg, as_stepped, as_line,
                    (sim.index.to_numpy(), sim["mean"].to_numpy(), sim["std"].to_numpy()), sm.output.design)
pd.DataFrame(dict(sigma_v_mpa=levels, prediction=pred, band_sd=band, property_sd=prop_sd,
                  mean_over_samples=prop_mean, lg_stepped=lg[0],
                  lg_brick=lg[1], as3700_stepped=as_stepped, as3700_line=as_line)).to_csv(
    sm.output.design_table, index=False, float_format="%.5g")
print(pd.DataFrame(rows).to_string())

eq_lines = []
for r in rows:
    if r["mode"] == "lower of two":
        eq_lines.append(f"- the predictor, {r['equation']} ({r['n']} runs): MAPE **{r['mape_pct']:.1f} %**, "
                        f"failure mode right in **{100 * r['mode_agreement']:.0f} %** of the runs")
    elif "alpha" in r:
        eq_lines.append(f"- {r['mode']} failure ({r['n']} runs): **{r['equation']}**, MAPE **{r['mape_pct']:.1f} %** "
                        f"on the runs it was fitted to, **{r['cv_mape_pct']:.1f} %** out of fold; "
                        f"alpha {r['alpha']:.3g}")
    else:
        eq_lines.append(f"- {r['mode']} failure ({r['n']} runs): {r['equation']}")
design_lines = []
for sv in sim.index:
    at = lambda y: float(np.interp(sv, levels, y))  # noqa: E731
    design_lines.append(f"- {sv:g} MPa: simulated **{sim.loc[sv, 'mean']:.3f} +- {sim.loc[sv, 'std']:.3f} MPa**, "
                        f"predicted **{at(pred):.3f} +- {at(band):.3f} MPa** at the mean properties, "
                        f"**{at(prop_mean):.3f} MPa** on average over the samples; Lourenco-Gaetani stepped {lg[0]:.3f} / "
                        f"brick {lg[1]:.3f} MPa; AS3700 stepped {at(as_stepped):.3f} / line {at(as_line):.3f} MPa")
F.write_captions(sm.input.templates, sm.output.captions, dict(
    equations=dict(lines="\n".join(eq_lines)),
    design_comparison=dict(f_tu=f_tu, f_tj=f_tj, resid=resid_sd, n_samples=runs["sample"].nunique(),
                           l_o=1e3 * l_o, h_b=1e3 * h_b, c_ratio=joints["c_ratio"],
                           equations="the joint and brick equations" if len(fits) == 2 else
                           f"the {next(iter(fits))} equation alone (too few runs of the other mode)" if fits
                           else "no equation (too few runs)", lines="\n".join(design_lines)),
))
