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
    "specimen/masonry.py": ["test_scene.py", "test_study.py", "test_potential_crack.py", "-k", "not carries_f_tu"],
    "specimen/quantities.py": ["test_units.py", "test_architecture.py", "-k", "not lint and not snakemake"],
    "specimen/row.py": ["test_architecture.py", "test_cli.py", "-k", "not lint and not snakemake"],
    "specimen/classify.py": ["test_classification.py"],
    "study/sampling.py": ["test_sampling.py"],
    "study/settings.py": ["test_study.py"],
    "study/file.py": ["test_studyfile.py", "test_architecture.py", "-k", "not lint and not snakemake"],
    "analysis/statistics.py": ["test_analysis.py", "test_intervals.py"],
    "analysis/equations.py": ["test_analysis.py", "test_regression.py", "test_intervals.py"],
    "analysis/sensitivity.py": ["test_sensitivity.py"],
    "analysis/fractiles.py": ["test_fractiles.py"],
    "analysis/brick_formats.py": ["test_formats.py"],
    "analysis/predict.py": ["test_check_predict.py"],
    "analysis/validation.py": ["test_tables.py", "test_intervals.py", "test_captions.py"],
    "report/captions.py": ["test_captions.py"],
}

# name, module, the text as it stands, the fault
FAULTS = [
    # masonry rules
    ("G_fu exponent's sign", "specimen/masonry.py", "(np.asarray(f_tu, float) / 1e6) ** exponent",
     "(np.asarray(f_tu, float) / 1e6) ** -exponent"),
    ("k_n: E_b + E_m", "specimen/masonry.py", "E_b * E_m / (t * (E_b - E_m))", "E_b * E_m / (t * (E_b + E_m))"),
    ("k_n of one unit only", "specimen/masonry.py", "joint_kn(0.5 * (E_a + E_b),", "joint_kn(0.5 * (E_a + E_a),"),
    ("c_u = f_tu", "specimen/masonry.py", "c=_frozen(c_ratio * ft), Gf=", "c=_frozen(ft), Gf="),
    ("G_II from f_t", "specimen/masonry.py", "GII=_frozen(GII_ratio * gi)", "GII=_frozen(GII_ratio * ft)"),
    ("crack planes swapped", "specimen/masonry.py", "return (1.0 - b) * L if k % 2 else b * L",
     "return b * L if k % 2 else (1.0 - b) * L"),
    ("G_I per f_tj in N/mm, not N/m", "specimen/masonry.py", "gi = _frozen(gi_per_ft * ft if",
     "gi = _frozen(1e3 * gi_per_ft * ft if"),
    # units and the row
    ("MPa 5 % too large", "specimen/quantities.py", 'SHOWN = {"Pa": ("MPa", 1e6, "mpa")',
     'SHOWN = {"Pa": ("MPa", 1.05e6, "mpa")'),
    ("a digit after a letter is not a power", "specimen/quantities.py", 'r"(?<=[A-Za-z])(\\d+)", r"^\\1"',
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
    ("a variable's mean its distribution's", "study/file.py",
     '**{v.setting: v.mean if v.mean is not None else float(v.frozen().mean())',
     '**{v.setting: float(v.frozen().median())'),
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
    ("higher of two", "analysis/equations.py", "return np.minimum(j, b), np.where(j <= b,",
     "return np.maximum(j, b), np.where(j <= b,"),
    ("folds of single runs", "analysis/equations.py", 'g.strength_mpa, g["sample"], terms, nested=nested)',
     "g.strength_mpa, np.arange(len(g)), terms, nested=nested)"),
    ("out-of-fold error of the fitted values", "analysis/equations.py", "cv_mape=mape(y, oof)",
     "cv_mape=mape(y, fitted)"),
    ("equations printed to three digits", "analysis/equations.py", "{abs(c):.4g} {k}", "{abs(c):.3g} {k}"),
    ("residual scatter with n", "analysis/equations.py", "resid_sd = float(np.std(ns.strength_mpa - low, ddof=1))",
     "resid_sd = float(np.std(ns.strength_mpa - low, ddof=0))"),
    ("a coefficient not brought back from the standardised scale", "analysis/equations.py",
     "coef = fit.coef / fit.scaler.scale_", "coef = fit.coef / fit.scaler.scale_ ** 0.95"),
    # sensitivity
    ("total index taken as the first-order one", "analysis/sensitivity.py",
     "np.array([total_order(a, ab[:, j], b) for j in range(d)])",
     "np.array([first_order(a, ab[:, j], b) for j in range(d)])"),
    ("inputs left in the variables' SI units", "analysis/sensitivity.py",
     "return np.column_stack([scale[n] * m.ppf(", "return np.column_stack([1.0 * m.ppf("),
    ("indices named after the wrong input", "analysis/sensitivity.py",
     "for k, col in enumerate(columns):\n            rows.append",
     "for k, col in enumerate(columns[::-1]):\n            rows.append"),
    ("the correlation taken for the values", "analysis/sensitivity.py", "r[i, j] = r[j, i] = rho",
     "r[i, j] = r[j, i] = 0.95 * rho"),
    # fractiles
    ("the logs' SD with n", "analysis/fractiles.py", "m, s, z = y.mean(), y.std(ddof=1),",
     "m, s, z = y.mean(), y.std(ddof=0),"),
    ("the 6 % fractile", "analysis/fractiles.py", "FRACTILE = 0.05 ", "FRACTILE = 0.06 "),
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
    # captions
    ("the overlap in cm", "report/captions.py", 'l_o=1e3 * inputs["l_o"]', 'l_o=1e2 * inputs["l_o"]'),
    ("the running mean's error with n", "report/captions.py", "se = g.P_max_kN.std(ddof=1) /",
     "se = g.P_max_kN.std(ddof=0) /"),
    ("a caption's correlation noise at n", "report/captions.py",
     'noise = f"+-{A.correlation_band(n_corr):.2f}', 'noise = f"+-{A.correlation_band(n_corr + 1):.2f}'),
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
