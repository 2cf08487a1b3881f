"""The test suite's teeth: seeded faults in the study's analysis, the
failure classification, the sampling, the masonry rules and the result
tables, each applied alone to the source, the tests that guard that
module run against it, the fault reverted.

    .venv/bin/python benchmarks/mutants.py [--tests DIR] [--only NAME ...]

A fault is caught when its tests fail.  Prints one line per fault and the
share caught; exits 1 if a fault survives.  ``--tests DIR``: the test files
of another version of the suite (the same names), to compare suites on the
same faults.  The source is restored after every fault, also on Ctrl-C.
"""
import argparse
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src" / "masonrydem"

# module -> the tests that guard it (pytest arguments, relative to the tests folder)
GUARDS = {
    "masonry.py": ["test_scene.py", "test_study.py", "test_potential_crack.py", "-k", "not carries_f_tu"],
    "analysis.py": ["test_analysis.py", "test_regression.py", "test_intervals.py"],
    "classify.py": ["test_classification.py"],
    "sampling.py": ["test_sampling.py"],
    "study.py": ["test_study.py"],
    "validation.py": ["test_tables.py", "test_intervals.py"],
}

# name, module, the text as it stands, the fault
FAULTS = [
    ("G_I twice the rule", "masonry.py", "GI_PER_FT = 0.03 * 1e3 / 1e6", "GI_PER_FT = 0.06 * 1e3 / 1e6"),
    ("G_fu exponent's sign", "masonry.py", "(np.asarray(f_tu, float) / 1e6) ** exponent",
     "(np.asarray(f_tu, float) / 1e6) ** -exponent"),
    ("k_n: E_b + E_m", "masonry.py", "E_b * E_m / (t * (E_b - E_m))", "E_b * E_m / (t * (E_b + E_m))"),
    ("k_n of one unit only", "masonry.py", "joint_kn(0.5 * (E_a + E_b),", "joint_kn(0.5 * (E_a + E_a),"),
    ("c_u = f_tu", "masonry.py", "c=_frozen(c_ratio * ft), Gf=", "c=_frozen(ft), Gf="),
    ("G_II from f_t", "masonry.py", "GII=_frozen(GII_ratio * gi)", "GII=_frozen(GII_ratio * ft)"),
    ("crack planes swapped", "masonry.py", "return (1.0 - b) * L if k % 2 else b * L",
     "return b * L if k % 2 else (1.0 - b) * L"),
    ("brick share over failed runs", "analysis.py", 'brick_share=float((good.failure_mode == "brick").mean())',
     'brick_share=float((g.failure_mode == "brick").mean())'),
    ("MAPE without abs", "analysis.py", "np.mean(np.abs((yhat - y) / y))", "np.mean((yhat - y) / y)"),
    ("higher of two", "analysis.py", "return np.minimum(j, b), np.where(j <= b,", "return np.maximum(j, b), np.where(j <= b,"),
    ("increase inverted", "analysis.py", "increase=g[high] / g[low] - 1.0", "increase=g[low] / g[high] - 1.0"),
    ("features f_tu, f_tj swapped", "analysis.py", "np.column_stack([f_tu, f_tj, f_tu ** 2",
     "np.column_stack([f_tj, f_tu, f_tu ** 2"),
    ("folds of single runs", "analysis.py", 'g.strength_mpa, g["sample"], nested=nested)',
     "g.strength_mpa, np.arange(len(g)), nested=nested)"),
    ("correlation of the other modes", "analysis.py", 'sel = g if mode == "all" else g[g.failure_mode == mode]\n'
     '            row', 'sel = g if mode == "all" else g[g.failure_mode != mode]\n            row'),
    ("scatter level off by one", "analysis.py", "return levels[np.argmin(np.abs(levels - near))]",
     "return levels[np.argmin(np.abs(levels - near)) - 1]"),
    ("resampled COV with n, not n - 1", "analysis.py", "/ (count - 1)) / mean", "/ count) / mean"),
    ("resampled increase from the second level", "analysis.py", "increase=mean[..., -1] / mean[..., 0] - 1.0",
     "increase=mean[..., -1] / mean[..., 1] - 1.0"),
    ("90 % intervals", "analysis.py", "CONFIDENCE = 0.95", "CONFIDENCE = 0.90"),
    ("scorecard: difference of the paper from ours", "validation.py", "100.0 * (ours / paper - 1.0)",
     "100.0 * (paper / ours - 1.0)"),
    ("cell cracked above, not at, the threshold", "classify.py", "cracked = dc >= crack_damage",
     "cracked = dc > crack_damage"),
    ("through above, not at, the share", "classify.py", "through = np.flatnonzero(fractions >= crack_through)",
     "through = np.flatnonzero(fractions > crack_through)"),
    ("bed joints not counted", "classify.py", 'mortar = np.array([kind != "crack" for', 'mortar = np.array([kind == "head" for'),
    ("interface cracked at half damage", "classify.py", "[D[c.sc] > 0.0]", "[D[c.sc] >= 0.5]"),
    ("correlation's sign", "sampling.py", "target[i, j] = target[j, i] = rho", "target[i, j] = target[j, i] = -rho"),
    ("lognormal scale: the mean", "sampling.py", "scale=self.mean / math.sqrt(1.0 + self.cov ** 2))",
     "scale=self.mean)"),
    ("E_b and f_tu swapped", "study.py", '("unit", "E", "E_b"), ("unit", "ft", "f_tu")',
     '("unit", "E", "f_tu"), ("unit", "ft", "E_b")'),
    ("change not relative", "validation.py", "100.0 * (p / ref[s] - 1.0)", "100.0 * (p / ref[s])"),
    ("good enough in any mode", "validation.py", "abs(change) <= tolerance\n                                          and "
     'r["failure_mode"] == full["failure_mode"]', "abs(change) <= tolerance"),
    ("half-rate change against itself", "validation.py", 'r["P_max_kN"] / results[case]["P_max_kN"]',
     'r["P_max_kN"] / results[run]["P_max_kN"]'),
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tests", default=str(ROOT / "tests"))
    ap.add_argument("--only", nargs="*")
    args = ap.parse_args()
    faults = [f for f in FAULTS if not args.only or f[0] in args.only]
    for module in sorted({m for _, m, _, _ in faults}):
        if not run_tests(args.tests, GUARDS[module]):
            sys.exit(f"the tests of {module} fail without a fault: fix them first")
    caught = 0
    for name, module, old, new in faults:
        path = SRC / module
        text = path.read_text()
        if text.count(old) != 1:
            sys.exit(f"fault {name!r}: its text is not once in {module}")
        t0 = time.perf_counter()
        try:
            path.write_text(text.replace(old, new))
            hit = not run_tests(args.tests, GUARDS[module])
        finally:
            path.write_text(text)
        caught += hit
        print(f"{'caught  ' if hit else 'SURVIVED'} {module:14s} {name}  ({time.perf_counter() - t0:.0f} s)", flush=True)
    print(f"{caught} of {len(faults)} faults caught ({100 * caught / len(faults):.0f} %)")
    return 0 if caught == len(faults) else 1


if __name__ == "__main__":
    sys.exit(main())
