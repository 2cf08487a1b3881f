"""The test suite's teeth: seeded faults, each a plausible slip in one line
of the package, many at the scale of a few per cent (a quantile, a
degree of freedom, a unit's size), applied alone to the source; the tests
that guard that module run against it; the fault reverted.

    .venv/bin/python benchmarks/mutants.py [--tests DIR] [--only NAME ...]

A fault is caught when its tests fail.  Prints one line per fault, the
faults caught per module and in all; exits 1 if a fault survives.  A fault
whose text is no longer once in its module is a failure of this tool, not
of the suite: every such fault is named and the tool exits 2 before any
fault runs.  ``--tests DIR``: the test files of another version of the
suite (the same names), to compare suites on the same faults.  The source
is restored after every fault, also on Ctrl-C.
"""
import argparse
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src" / "masonrydem"

# module -> the tests that guard it (pytest arguments, relative to the tests folder)
GUARDS = {
    "scene/masonry.py": ["test_scene.py", "test_study.py", "test_potential_crack.py", "-k", "not carries_f_tu"],
    "scene/quantities.py": ["test_units.py", "test_architecture.py", "-k", "not lint and not snakemake"],
    "specimen/row.py": ["test_architecture.py", "test_cli.py", "-k", "not lint and not snakemake"],
    "specimen/classify.py": ["test_classification.py"],
    "study/sampling.py": ["test_sampling.py"],
    "study/copula.py": ["test_sensitivity.py", "test_sobol_check.py"],
    "study/settings.py": ["test_study.py"],
    "study/file.py": ["test_studyfile.py", "test_architecture.py", "-k", "not lint and not snakemake"],
    "study/typed.py": ["test_studyfile.py", "test_architecture.py", "-k", "not lint and not snakemake"],
    "analysis/statistics.py": ["test_analysis.py", "test_intervals.py"],
    "analysis/equations.py": ["test_analysis.py", "test_regression.py", "test_intervals.py"],
    "analysis/sensitivity.py": ["test_sensitivity.py"],
    "analysis/sobol_check.py": ["test_sobol_check.py"],
    "analysis/fractiles.py": ["test_fractiles.py", "test_design.py"],
    "analysis/needs.py": ["test_fractiles.py", "test_design.py"],
    "analysis/brick_formats.py": ["test_formats.py"],
    "analysis/predict.py": ["test_check_predict.py"],
    "study/terms.py": ["test_terms.py", "test_studyfile.py"],
    "analysis/validation.py": ["test_tables.py", "test_intervals.py", "test_captions.py"],
    "report/captions.py": ["test_captions.py"],
    "report/landing.py": ["test_printed_numbers.py", "-k", "code_writes"],
    "analysis/labfit.py": ["test_labfit.py"],
    "analysis/labsheet.py": ["test_labsheet.py", "test_labfit.py", "-k", "not anderson_darling"],
    "analysis/design.py": ["test_design.py"],
}

# name, module, the text as it stands, the fault
FAULTS = [
    # masonry rules
    ("G_fu exponent's sign", "scene/masonry.py", "(np.asarray(f_tu, float) / 1e6) ** exponent",
     "(np.asarray(f_tu, float) / 1e6) ** -exponent"),
    ("k_n: E_b + E_m", "scene/masonry.py", "E_b * E_m / (t * (E_b - E_m))", "E_b * E_m / (t * (E_b + E_m))"),
    ("k_n of one unit only", "scene/masonry.py", "joint_kn(0.5 * (E_a + E_b),", "joint_kn(0.5 * (E_a + E_a),"),
    ("c_u = f_tu", "scene/masonry.py", "c=_frozen(c_ratio * ft), Gf=", "c=_frozen(ft), Gf="),
    ("G_II from f_t", "scene/masonry.py", "GII=_frozen(GII_ratio * gi)", "GII=_frozen(GII_ratio * ft)"),
    ("crack planes swapped", "scene/masonry.py", "return (1.0 - b) * L if k % 2 else b * L",
     "return b * L if k % 2 else (1.0 - b) * L"),
    ("G_I per f_tj in N/mm, not N/m", "scene/masonry.py", "gi = _frozen(gi_per_ft * ft if",
     "gi = _frozen(1e3 * gi_per_ft * ft if"),
    # units and the row
    ("MPa 5 % too large", "scene/quantities.py", 'SHOWN = {"Pa": ("MPa", 1e6, "mpa")',
     'SHOWN = {"Pa": ("MPa", 1.05e6, "mpa")'),
    ("a digit after a letter is not a power", "scene/quantities.py", 'r"(?<=[A-Za-z])(\\d+)", r"^\\1"',
     'r"(?<=[A-Za-z])(\\d+)", r"\\1"'),
    ("a refused sample's inputs in SI", "specimen/row.py",
     "out[column(name, unit)] = to_shown(float(np.mean(sample[name])), unit)",
     "out[column(name, unit)] = float(np.mean(sample[name]))"),
    ("the row's strength 5 % low", "specimen/row.py", "strength_mpa=sp.strength(peak_P) / 1e6",
     "strength_mpa=sp.strength(peak_P) / 1.05e6"),
    # classification
    ("cell cracked above, not at, the threshold", "specimen/classify.py", "cracked = dc >= crack_damage",
     "cracked = dc > crack_damage"),
    ("through above, not at, the share", "specimen/classify.py", "through = np.flatnonzero(fractions >= crack_through)",
     "through = np.flatnonzero(fractions > crack_through)"),
    ("bed joints not counted", "specimen/classify.py", 'mortar = np.array([kind != "crack" for',
     'mortar = np.array([kind == "head" for'),
    ("interface cracked at half damage", "specimen/classify.py", "[D[c.sc] > 0.0]", "[D[c.sc] >= 0.5]"),
    ("a cell's damage not weighted by volume", "specimen/classify.py",
     "dc = (d[s:e].reshape(-1, 10) * w).sum(axis=1) / w.sum(axis=1)", "dc = d[s:e].reshape(-1, 10).mean(axis=1)"),
    ("a joint's damage not weighted by area", "specimen/classify.py", "num[j] += np.sum(D[c.sc] * area[c.sc])",
     "num[j] += np.sum(D[c.sc]) * np.mean(area[c.sc])"),
    # the study: its file, its sampling, its samples' settings
    ("correlation's sign", "study/sampling.py", "target[i, j] = target[j, i] = rho",
     "target[i, j] = target[j, i] = -rho"),
    ("lognormal scale: the mean", "study/sampling.py", "self.mean / math.sqrt(1.0 + cov ** 2))",
     "self.mean)"),
    ("per-item settings from the wall's key", "study/settings.py", "out[item + v.setting[len(wall):]]",
     "out[wall + v.setting[len(wall):]]"),
    ("a study file's correlation negated", "study/file.py", 'out[(a, b)] = float(c["rho"])',
     'out[(a, b)] = -float(c["rho"])'),
    ("the regression on the first variant, not the first per wallette", "study/file.py",
     'next((n for n, v in variants.items() if v["draw"] == "wallette"), None)', "next(iter(variants), None)"),
    ("a variable's mean its distribution's", "study/typed.py",
     'return v.mean if v.mean is not None else float(v.frozen().mean())',
     'return float(v.frozen().median())'),
    # statistics
    ("brick share over failed runs", "analysis/statistics.py",
     '"brick_share": float((good.failure_mode == "brick").mean())',
     '"brick_share": float((g.failure_mode == "brick").mean())'),
    ("increase inverted", "analysis/statistics.py", "increase=g[high] / g[low] - 1.0", "increase=g[low] / g[high] - 1.0"),
    ("correlation of the other modes", "analysis/statistics.py",
     'sel = g if mode == "all" else g[g.failure_mode == mode]\n            row',
     'sel = g if mode == "all" else g[g.failure_mode != mode]\n            row'),
    ("scatter level off by one", "analysis/statistics.py", "return levels[np.argmin(np.abs(levels - near))]",
     "return levels[np.argmin(np.abs(levels - near)) - 1]"),
    ("resampled COV with n, not n - 1", "analysis/statistics.py", "/ (count - 1)) / mean", "/ count) / mean"),
    ("resampled increase from the second level", "analysis/statistics.py",
     "increase=mean[..., -1] / mean[..., 0] - 1.0", "increase=mean[..., -1] / mean[..., 1] - 1.0"),
    ("90 % intervals", "analysis/statistics.py", "CONFIDENCE = 0.95", "CONFIDENCE = 0.90"),
    # equations
    ("MAPE without abs", "analysis/equations.py", "np.mean(np.abs((yhat - y) / y))", "np.mean((yhat - y) / y)"),
    ("higher of two", "analysis/equations.py", "return np.minimum(joint, brick), np.where(joint <= brick,",
     "return np.maximum(joint, brick), np.where(joint <= brick,"),
    ("folds of single runs", "analysis/equations.py", "fit_features(X[k], y[k], sample[k], terms, nested=nested)",
     "fit_features(X[k], y[k], np.arange(k.sum()), terms, nested=nested)"),
    ("out-of-fold error of the fitted values", "analysis/equations.py", "cv_mape=mape(y, oof)",
     "cv_mape=mape(y, fitted)"),
    ("equations printed to three digits", "analysis/equations.py", "{abs(c):.4g} {k}", "{abs(c):.3g} {k}"),
    ("residual scatter with n", "analysis/equations.py", "resid_sd = float(np.std(y - low, ddof=1))",
     "resid_sd = float(np.std(y - low, ddof=0))"),
    ("a coefficient not brought back from the standardised scale", "analysis/equations.py",
     "coef = fit.coef / fit.scaler.scale_", "coef = fit.coef / fit.scaler.scale_ ** 0.95"),
    # sensitivity
    ("total index taken as the first-order one", "analysis/sensitivity.py",
     "st = np.array([total_order(a, y[:, 1 + j], b) for j in range(d)])",
     "st = np.array([first_order(a, y[:, 1 + j], b) for j in range(d)])"),
    ("inputs left in the variables' SI units", "study/copula.py",
     "return np.column_stack([s * m.ppf(", "return np.column_stack([1.0 * m.ppf("),
    ("the runs' values taken in the variables' SI units", "study/copula.py",
     "m.cdf(np.asarray(x, float)[:, k] / self.scale[k])", "m.cdf(np.asarray(x, float)[:, k])"),
    ("indices named after the wrong input", "analysis/sensitivity.py",
     "for k, col in enumerate(columns):\n            rows.append",
     "for k, col in enumerate(columns[::-1]):\n            rows.append"),
    ("the correlation taken for the values", "study/copula.py", "r[i, j] = r[j, i] = rho",
     "r[i, j] = r[j, i] = 0.95 * rho"),
    ("the misfit left out of the interval: draws without their prior part", "analysis/sensitivity.py",
     "theta = np.column_stack([np.zeros(features), rng.standard_normal((features, draws))])",
     "theta = np.zeros((features, 1 + draws))"),
    ("the draws' length scales in the wrong order", "analysis/sensitivity.py",
     "rng.standard_normal((features, w_at.shape[1])) / ls",
     "rng.standard_normal((features, w_at.shape[1])) / ls[::-1]"),
    ("the 5 and 95 % points of the draws", "analysis/sensitivity.py", "tail = 50 * (1 - CONFIDENCE)",
     "tail = 100 * (1 - CONFIDENCE)"),
    ("the draws' percentiles without their reflection", "analysis/sensitivity.py",
     "lo, hi = np.minimum(lo, 2 * estimate - hi), np.maximum(hi, 2 * estimate - lo)", "lo, hi = lo, hi"),
    ("the subset's parameters not rescaled to all the runs", "analysis/sensitivity.py",
     "k, scale = gp.kernel_, (gp._y_train_std / np.std(y)) ** 2", "k, scale = gp.kernel_, 1.0"),
    ("the subset's noise not rescaled with its amplitude", "analysis/sensitivity.py",
     "k.k2.noise_level * scale)", "k.k2.noise_level)"),
    ("the no-effect test the wrong way round", "analysis/sensitivity.py",
     "red.log_marginal_likelihood_value_) < crit)", "red.log_marginal_likelihood_value_) > crit)"),
    ("no interval reaching 0 where no effect is told", "analysis/sensitivity.py",
     "np.where(no_effect, 0.0, np.clip(lo, 0.0, 1.0))", "np.clip(lo, 0.0, 1.0)"),
    ("leave-one-out residuals without 1 / (K^-1)_ii", "analysis/sensitivity.py",
     "loo = (k_inv @ gp.y_train_) / np.diag(k_inv) * gp._y_train_std",
     "loo = (k_inv @ gp.y_train_) * np.diag(k_inv) * gp._y_train_std"),
    ("the draws' indices not centred", "analysis/sensitivity.py", "y = (y - y.mean(axis=0)).reshape(n, d + 2, -1)",
     "y = y.reshape(n, d + 2, -1)"),
    # the Sobol check on the solver
    ("the direct estimates not centred", "analysis/sobol_check.py", "y = (y - y.mean()) / y.std()", "y = y / y.std()"),
    ("a base row with a failed run kept", "analysis/sobol_check.py",
     "keep = ok.all(axis=1) & np.isfinite(y).all(axis=1)", "keep = np.isfinite(y).all(axis=1)"),
    ("the direct intervals at 90 %", "analysis/sobol_check.py",
     "[50 * (1 - confidence), 50 * (1 + confidence)]", "[100 * (1 - confidence), 100 * confidence]"),
    ("the resamples of single runs, not base rows", "analysis/sobol_check.py",
     "_estimates(y[rng.integers(0, len(y), len(y))])",
     "_estimates(y.ravel()[rng.integers(0, y.size, y.size)].reshape(y.shape))"),
    ("the distance outside measured to the far end", "analysis/sobol_check.py",
     "max(lo - x, x - hi, 0.0) if x == x else x", "max(hi - x, x - lo, 0.0) if x == x else x"),
    ("the total index by the first-order estimator", "analysis/sobol_check.py",
     "np.array([total_order(a, ab[:, j], b) for j in range(ab.shape[1])])",
     "np.array([first_order(a, ab[:, j], b) for j in range(ab.shape[1])])"),
    # fractiles
    ("the logs' SD with n", "analysis/fractiles.py", "m, s, z = y.mean(), y.std(ddof=1),",
     "m, s, z = y.mean(), y.std(ddof=0),"),
    ("the 6 % fractile", "analysis/needs.py", "FRACTILE = 0.05 ", "FRACTILE = 0.06 "),
    ("the noncentrality's sign", "analysis/fractiles.py", "nc=-z * np.sqrt(n))", "nc=z * np.sqrt(n))"),
    # brick formats
    ("every variant scored", "analysis/brick_formats.py", "ok = runs[runs.ok & (runs.variant == variant)]",
     "ok = runs[runs.ok]"),
    ("bias of the simulated over the predicted", "analysis/brick_formats.py",
     "bias_pct=float(100 * np.mean(strength / y - 1))", "bias_pct=float(100 * np.mean(y / strength - 1))"),
    # predict
    ("the interval's 5 % quantile", "analysis/predict.py", "np.quantile(ratio, 0.025)", "np.quantile(ratio, 0.05)"),
    ("the interval from the fitted, not the out-of-fold, strengths", "analysis/predict.py",
     'ratio = g_mode.strength_mpa.to_numpy() / eq["cv_predicted"]', 'ratio = g_mode.strength_mpa.to_numpy() / eq["fitted"]'),
    ("the higher equation governs", "analysis/predict.py", "mode = min(by_mode, key=by_mode.get)",
     "mode = max(by_mode, key=by_mode.get)"),
    # predict, the equations and their terms
    ("the first mode's ratios whatever mode governs", "analysis/predict.py",
     "by_mode[m] * modes[m][q] for m in by_mode", "by_mode[m] * next(iter(modes.values()))[q] for m in by_mode"),
    ("the governing mode's interval alone", "analysis/predict.py", 'interval = _interval(p["modes"], by_mode)',
     'interval = _interval(p["modes"], {mode: s})'),
    ("each bound the higher of the modes'", "analysis/predict.py", "return tuple(min(by_mode[m]",
     "return tuple(max(by_mode[m]"),
    ("the interval's 95 % upper quantile", "analysis/predict.py", "np.quantile(ratio, 0.975)",
     "np.quantile(ratio, 0.95)"),
    ("the lower-of-two MAPE interval from the joint fit", "analysis/equations.py",
     '[rows.get("lower of two", {}).get("mape_pct", np.nan)]', '[rows.get("joint", {}).get("mape_pct", np.nan)]'),
    ("'^' read as a product", "study/terms.py", 'term.replace("^", "**")', 'term.replace("^", "*")'),
    ("a unary minus dropped", "study/terms.py", "ast.USub: operator.neg", "ast.USub: operator.pos"),
    ("a binary operator's operands swapped", "study/terms.py", "(value(node.left), value(node.right))",
     "(value(node.right), value(node.left))"),
    ("division as floor division", "study/terms.py", "ast.Div: operator.truediv", "ast.Div: operator.floordiv"),
    ("a term's inputs in the order the tree is walked", "study/terms.py", "for _, name in sorted(names)",
     "for _, name in names"),
    # validation tables and the scorecard
    ("scorecard: difference of the paper from ours", "analysis/validation.py", "100.0 * (ours / paper - 1.0)",
     "100.0 * (paper / ours - 1.0)"),
    ("change not relative", "analysis/validation.py", "100.0 * (p / ref[s] - 1.0)", "100.0 * (p / ref[s])"),
    ("good enough in any mode", "analysis/validation.py", "abs(change) <= tolerance\n                                          "
     'and r["failure_mode"] == full["failure_mode"]', "abs(change) <= tolerance"),
    ("half-rate change against itself", "analysis/validation.py", 'r["P_max_kN"] / results[case]["P_max_kN"]',
     'r["P_max_kN"] / results[run]["P_max_kN"]'),
    ("the design band without the residual", "analysis/validation.py",
     "band = np.sqrt(prop_sd ** 2 + resid_sd ** 2)", "band = prop_sd"),
    # the lab fit, the lab sheet and the design value
    ("the Weibull's logs tested as a Gumbel of the maximum", "analysis/labfit.py",
     "stats.goodness_of_fit(stats.gumbel_l, np.log(x)", "stats.goodness_of_fit(stats.gumbel_r, np.log(x)"),
    ("a study file's family the best of all three", "analysis/labfit.py",
     'dist = distribution or choose(fits, STUDY_FAMILIES)["best"]', 'dist = distribution or choose(fits)["best"]'),
    ("the tolerance bound's s with n", "analysis/labfit.py",
     "tolerance_factor(y.size, content, conf) * y.std(ddof=1)", "tolerance_factor(y.size, content, conf) * y.std(ddof=0)"),
    ("the tolerance factor's non-centrality with n - 1", "analysis/labfit.py",
     "stats.norm.ppf(content) * math.sqrt(n)) / math.sqrt(n)", "stats.norm.ppf(content) * math.sqrt(n - 1)) / math.sqrt(n)"),
    ("the fractile interval at 90 % by default", "analysis/labfit.py", 'def fractile_interval(x, distribution, p=0.05, conf=0.95)',
     'def fractile_interval(x, distribution, p=0.05, conf=0.90)'),
    ("the block's fractile interval at 90 %", "analysis/labfit.py", "lo, hi = fractile_interval(x, dist)",
     "lo, hi = fractile_interval(x, dist, conf=0.90)"),
    ("the block's tolerance bound of 90 % content", "analysis/labfit.py", "q(tolerance_bound(x, dist))",
     "q(tolerance_bound(x, dist, content=0.90))"),
    ("the mean's interval with the normal's quantile", "analysis/labfit.py",
     "stats.t.ppf(0.5 + conf / 2, x.size - 1)", "stats.norm.ppf(0.5 + conf / 2)"),
    ("the exact COV interval with s over n", "analysis/labfit.py", "n, m, s = x.size, x.mean(), x.std(ddof=1)",
     "n, m, s = x.size, x.mean(), x.std(ddof=0)"),
    ("s_y of a known V_X taken as V_X", "analysis/labfit.py", "math.sqrt(math.log(1 + prior_cov ** 2)) if known",
     "prior_cov if known"),
    ("Z over the width, not the depth", "analysis/labsheet.py", "Z, A = b * d ** 2 / 6.0, b * d",
     "Z, A = b ** 2 * d / 6.0, b * d"),
    ("the unit's weight left out", "analysis/labsheet.py", "(F1 * e1 + F2 * e2) / Z - (F1 + F2 + F3) / A",
     "(F1 * e1 + F2 * e2) / Z - (F1 + F2) / A"),
    ("the wrench's weight at the load's lever arm", "analysis/labsheet.py", 'c.get("F2", 0.0), c.get("e2", 0.0)',
     'c.get("F2", 0.0), c["e1"]'),
    ("four-point moment P (L - L_i / 2) / 4", "analysis/labsheet.py", "3.0 * P * (L - L_i) / (2.0 * b * d ** 2)",
     "3.0 * P * (L - L_i / 2) / (2.0 * b * d ** 2)"),
    ("a four-point sheet worked as three-point", "analysis/labsheet.py",
     'flexural_strength(c["P"], c["L"], c["b"], c["d"], c.get("L_i", 0.0))', 'flexural_strength(c["P"], c["L"], c["b"], c["d"])'),
    ("EN 1992's depth in cm", "analysis/labsheet.py", "max(1.6 - depth * 1e3 / 1000.0, 1.0)",
     "max(1.6 - depth * 1e2 / 1000.0, 1.0)"),
    ("a joint failure not kept", "analysis/labsheet.py", '"keep": ("", "ok", "valid", "bond", "joint")',
     '"keep": ("", "ok", "valid", "bond")'),
    ("a load span as long as the span accepted", "analysis/labsheet.py", 'if c.get("L_i", 0.0) >= c["L"]:',
     'if c.get("L_i", 0.0) > c["L"]:'),
    ("a results column in Pa whatever the study's unit", "analysis/labsheet.py",
     'SYMBOLS[k][0] if form != "results" else unit', 'SYMBOLS[k][0] if form != "results" else "Pa"'),
    ("a lab's computed strength checked without its rounding", "analysis/labsheet.py",
     'LAB_TOLERANCE * v + c["lab_rounding"]', 'LAB_TOLERANCE * v'),
    ("the conversion's depth from the width column", "analysis/labsheet.py", 'np.mean([c["d"] for _, c in cells])',
     'np.mean([c["b"] for _, c in cells])'),
    ("the lab draws' spread with n degrees of freedom", "analysis/design.py", "g.chisquare(n - 1, draws)",
     "g.chisquare(n, draws)"),
    ("the fit's cov with n", "analysis/design.py", "return m, np.std(x, -1, ddof=1) / m", "return m, np.std(x, -1, ddof=0) / m"),
    ("the lab draws' mean at the fit's spread", "analysis/design.py",
     "mu_d = mu - g.standard_normal(draws) * s_d / math.sqrt(n)", "mu_d = mu - g.standard_normal(draws) * s / math.sqrt(n)"),
    ("the draws' 5 % and 95 % percentiles", "analysis/design.py", "a = 100 * (1 - conf) / 2", "a = 100 * (1 - conf)"),
    ("the runs' pivot with ESS degrees of freedom", "analysis/design.py", "g.chisquare(n - 1))", "g.chisquare(n))"),
    ("the mean without its control variate", "analysis/design.py", "/ sw + (b * (EU - ", "/ sw + 0 * (b * (EU - "),
    ("the corrected variance over the sum of weights", "analysis/design.py", "denom = sw - np.square(w).sum(-1) / sw",
     "denom = sw"),
    ("the runs-only interval at 90 %", "analysis/design.py", "fractiles.empirical_fractile)(y)",
     "fractiles.empirical_fractile)(y, confidence=0.90)"),
    ("the point at the unweighted runs", "analysis/design.py", '"point": float(weighted_fractile(y, w_hat, p, basis))',
     '"point": float(weighted_fractile(y, np.ones_like(w_hat), p, basis))'),
    ("the lognormal's sigma taken as its cov", "analysis/design.py", "s = np.sqrt(np.log1p(np.square(cov)))",
     "s = np.asarray(cov)"),
    ("the weighted variance over the sum of weights", "analysis/design.py",
     "/ (sw - np.square(w).sum(-1) / sw)", "/ sw"),
    # captions
    ("the overlap in cm", "report/captions.py", "{1e3 * inputs['l_o']:.0f}", "{1e2 * inputs['l_o']:.0f}"),
    ("the running mean's error with n", "report/captions.py", "se = g.P_max_kN.std(ddof=1) /",
     "se = g.P_max_kN.std(ddof=0) /"),
    ("a caption's correlation noise at n", "report/captions.py",
     'noise = f"+-{A.correlation_band(n_corr):.2f}', 'noise = f"+-{A.correlation_band(n_corr + 1):.2f}'),
    # the landing page
    ("the summed run time not per lane", "report/landing.py",
     'np.sum(runs.get("wall_time_s", np.nan) / runs.get("lanes", 1))', 'np.sum(runs.get("wall_time_s", np.nan))'),
    ("core-minutes in hours", "report/landing.py", 'f"{seconds / 60:.1f} core-minutes"',
     'f"{seconds / 3600:.1f} core-minutes"'),
    ("the key table's brick share as a fraction", "report/landing.py", 'f"{100 * r.brick_share:.0f}"',
     'f"{r.brick_share:.0f}"'),
    ("the samples counted as the largest number", "report/landing.py", 'n_samples=runs["sample"].nunique()',
     'n_samples=runs["sample"].max()'),
    ("the model-form band in per mille", "report/landing.py", "r.ours * (1 + lo / 100)", "r.ours * (1 + lo / 1000)"),
    ("a level between the band's: the lower one alone", "report/landing.py",
     "[max([x for x in at if x < sv], default=at[0]), min([x for x in at if x > sv], default=at[-1])]",
     "[max([x for x in at if x < sv], default=at[0])]"),
    ("our interval's ends swapped", "report/landing.py", 'f"{r.ours:.2f} ({r.ours_lo:.2f} to {r.ours_hi:.2f})"',
     'f"{r.ours:.2f} ({r.ours_hi:.2f} to {r.ours_lo:.2f})"'),
]


def run_tests(tests, args):
    """True when the tests pass (or there are none: a suite without the
    guard's files, or whose tests the guard's -k selects none of)."""
    files = [str(Path(tests) / a) if a.endswith(".py") else a for a in args]
    files = [f for f in files if not f.endswith(".py") or Path(f).exists()]
    if not any(f.endswith(".py") for f in files):
        return True
    r = subprocess.run([sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "-m", "",
                        f"--rootdir={ROOT}", *files], cwd=ROOT, capture_output=True, text=True)
    return r.returncode in (0, 5)         # 5: no test collected


def stale(faults):
    """The faults whose text is not once in their module: (name, module,
    how many times)."""
    return [(name, module, (SRC / module).read_text().count(old)) for name, module, old, _ in faults
            if (SRC / module).read_text().count(old) != 1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tests", default=str(ROOT / "tests"))
    ap.add_argument("--only", nargs="*")
    args = ap.parse_args()
    faults = [f for f in FAULTS if not args.only or f[0] in args.only]
    bad = stale(faults)
    for name, module, count in bad:
        print(f"TOOL FAILURE: fault {name!r}: its text is {count} times in {module}, not once: mend the fault",
              flush=True)
    if bad:
        return 2
    for module in sorted({m for _, m, _, _ in faults}):
        if not run_tests(args.tests, GUARDS[module]):
            sys.exit(f"the tests of {module} fail without a fault: fix them first")
    caught, per_module = Counter(), Counter()
    for name, module, old, new in faults:
        path = SRC / module
        text = path.read_text()
        t0 = time.perf_counter()
        try:
            path.write_text(text.replace(old, new))
            hit = not run_tests(args.tests, GUARDS[module])
        finally:
            path.write_text(text)
        caught[module] += hit
        per_module[module] += 1
        print(f"{'caught  ' if hit else 'SURVIVED'} {module:26s} {name}  ({time.perf_counter() - t0:.0f} s)",
              flush=True)
    for module in sorted(per_module):
        print(f"{module:26s} {caught[module]} of {per_module[module]} caught")
    total = sum(caught.values())
    print(f"{total} of {len(faults)} faults caught ({100 * total / len(faults):.0f} %)")
    return 0 if total == len(faults) else 1


if __name__ == "__main__":
    sys.exit(main())
