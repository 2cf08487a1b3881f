"""Characteristic strengths: the 5 % fractile of the study's strengths per
variant and level, with confidence intervals, estimated two ways.

- **Lognormal**: the logs y = ln f of the n strengths are taken as normal,
  and the p-fractile is exp(ybar + z_p s).  Its interval is exact: with
  y_p = mu + z_p sigma the true fractile of the logs,
  sqrt(n) (ybar - y_p) / s follows the noncentral t distribution with
  n - 1 degrees of freedom and noncentrality -z_p sqrt(n) (the statistic
  behind one-sided tolerance limits, the k-factors of EN 1990 Annex D and
  ISO 16269-6), so the quantiles of that distribution bound y_p.
- **Non-parametric** (no distribution assumed): the sample quantile, and
  as interval the order statistics x_(r) <= x_p <= x_(s), whose coverage
  is B(s - 1; n, p) - B(r - 1; n, p) for a continuous distribution, with B
  the binomial distribution function.  r is the highest rank with
  B(r - 1) <= alpha/2 and s the lowest with B(s - 1) >= 1 - alpha/2, so the
  coverage is at least the confidence asked for; where no rank satisfies
  one side (the lower one below n = 72 for p = 5 % at 95 %: 0.95^n > 0.025) that
  bound is undefined.

Which of the two the data support: Shapiro-Wilk on the logs; p >= 0.05
keeps the lognormal one (the narrower interval), otherwise the
non-parametric one stands; below 3 runs neither is given.
"""
import numpy as np
import pandas as pd
from scipy import stats

from .needs import CONFIDENCE, FRACTILE
NORMALITY_P = 0.05       # Shapiro-Wilk: below it, the logs are taken as not normal


def lognormal_fractile(x, p=FRACTILE, confidence=CONFIDENCE):
    """(estimate, lo, hi) of the p-fractile of positive values x taken as
    lognormal, with the exact two-sided interval of the given confidence."""
    y = np.log(np.asarray(x, float))
    n = y.size
    if n < 3 or np.any(~np.isfinite(y)):
        return np.nan, np.nan, np.nan
    m, s, z = y.mean(), y.std(ddof=1), stats.norm.ppf(p)
    a = (1 - confidence) / 2
    t_lo, t_hi = stats.nct.ppf([a, 1 - a], df=n - 1, nc=-z * np.sqrt(n))
    return float(np.exp(m + z * s)), float(np.exp(m - t_hi * s / np.sqrt(n))), float(np.exp(m - t_lo * s / np.sqrt(n)))


def order_ranks(n, p=FRACTILE, confidence=CONFIDENCE):
    """The 1-based ranks (r, s) of the order statistics that bound the
    p-fractile with at least the given confidence (module docstring), each
    None where no rank gives its side, and their exact coverage."""
    a = (1 - confidence) / 2
    cdf = stats.binom.cdf(np.arange(n + 1), n, p)     # cdf[k] = B(k; n, p)
    low = np.flatnonzero(cdf[:n] <= a)                 # r - 1 = k with B(k) <= a
    high = np.flatnonzero(cdf[:n] >= 1 - a)            # s - 1 = k with B(k) >= 1 - a
    r = int(low[-1]) + 1 if low.size else None
    s = int(high[0]) + 1 if high.size else None
    coverage = (cdf[s - 1] if s else 1.0) - (cdf[r - 1] if r else 0.0)
    return r, s, float(coverage)


def empirical_fractile(x, p=FRACTILE, confidence=CONFIDENCE):
    """(estimate, lo, hi) of the p-fractile of x without a distribution: the
    sample quantile (linear interpolation) and the order statistics of
    order_ranks (NaN where a side has none)."""
    x = np.sort(np.asarray(x, float))
    if x.size == 0:
        return np.nan, np.nan, np.nan
    r, s, _ = order_ranks(x.size, p, confidence)
    return (float(np.quantile(x, p)), float(x[r - 1]) if r else np.nan, float(x[s - 1]) if s else np.nan)


def lognormal_fit(x):
    """Shapiro-Wilk's p-value for the logs of x (NaN for fewer than 3)."""
    y = np.log(np.asarray(x, float))
    return float(stats.shapiro(y).pvalue) if y.size >= 3 else np.nan


def characteristic_table(runs, level, column="strength_mpa", p=FRACTILE, confidence=CONFIDENCE):
    """One row per variant and level of the runs that reached their stop
    criteria (``ok``; all failure modes together): the count, the mean,
    both estimates with their intervals, the order ranks, Shapiro-Wilk's
    p-value on the logs, which estimate the data support and its value."""
    rows = []
    for (variant, lv), g in runs[runs.ok].groupby(["variant", level.column]):
        x = g[column].to_numpy(float)
        ln, ln_lo, ln_hi = lognormal_fractile(x, p, confidence)
        em, em_lo, em_hi = empirical_fractile(x, p, confidence)
        r, s, coverage = order_ranks(x.size, p, confidence)
        p_sw = lognormal_fit(x)
        basis = ("too few runs" if np.isnan(p_sw) else "lognormal" if p_sw >= NORMALITY_P else "non-parametric")
        rows.append({"variant": variant, level.column: lv, "n": x.size, "mean_mpa": x.mean(),
                     "lognormal_mpa": ln, "lognormal_mpa_lo": ln_lo, "lognormal_mpa_hi": ln_hi,
                     "empirical_mpa": em, "empirical_mpa_lo": em_lo, "empirical_mpa_hi": em_hi,
                     "rank_lo": r, "rank_hi": s, "rank_coverage": coverage, "shapiro_p_log": p_sw,
                     "supported": basis,
                     "characteristic_mpa": {"lognormal": ln, "non-parametric": em}.get(basis, np.nan)})
    return pd.DataFrame(rows).astype({"rank_lo": "Int64", "rank_hi": "Int64"})


def with_design(table, design, level):
    """The table with the design rules of the study's design comparison
    (regression's design_comparison.csv: Lourenco-Gaetani lg_*, AS3700
    as3700_*, at the mean properties) at its levels, where that comparison
    is over the same swept setting."""
    if level.column not in design:
        return table
    cols = [c for c in design.columns if c.startswith(("lg_", "as3700_"))]
    at = {f"{c}_mpa": np.interp(table[level.column], design[level.column], design[c]) for c in cols}
    return table.assign(**at)


def _mpa(x):
    return "none (too few runs)" if pd.isna(x) else f"{x:.3f}"


def span(lo, hi, spec=".3f", unit=""):
    """An interval's ends in words, 'lo to hi unit'; an end that too few
    runs cannot give is named as missing, not printed as a number."""
    if pd.isna(lo) and pd.isna(hi):
        return "no interval at this many runs"
    if pd.isna(lo):
        return f"no lower end at this many runs, up to {format(hi, spec)}{unit}"
    if pd.isna(hi):
        return f"from {format(lo, spec)}{unit}, no upper end at this many runs"
    return f"{format(lo, spec)} to {format(hi, spec)}{unit}"


def caption_values(table, level):
    """The characteristic caption's numbers: one line per variant and level."""
    lines = []
    for r in table.itertuples(index=False):
        rd = r._asdict()
        design = ", ".join(f"{k[:-4].replace('_', ' ')} {v:.3f}" for k, v in rd.items()
                           if k.startswith(("lg_", "as3700_")))
        p_sw = "not computed (fewer than 3 runs)" if pd.isna(r.shapiro_p_log) else f"{r.shapiro_p_log:.2f}"
        lines.append(f"{r.variant}, {level.text(rd[level.column])}: **{_mpa(r.characteristic_mpa)} MPa** "
                     f"({r.supported}; {r.n} runs, mean {r.mean_mpa:.3f} MPa); lognormal {_mpa(r.lognormal_mpa)} "
                     f"({span(r.lognormal_mpa_lo, r.lognormal_mpa_hi)}), non-parametric "
                     f"{_mpa(r.empirical_mpa)} ({span(r.empirical_mpa_lo, r.empirical_mpa_hi)}), "
                     f"Shapiro-Wilk p on the logs {p_sw}" + (f"; design rules at the mean properties: {design} MPa"
                                                             if design else ""))
    supported = int((table.supported == "lognormal").sum())
    n = int(table.n.max()) if len(table) else 0
    r, s, coverage = order_ranks(n) if n else (None, None, 0.0)
    ranks = (f"for {n} runs the order statistics {r} and {s} from the smallest, coverage {100 * coverage:.1f} %"
             if r and s else f"for {n} runs no order statistic bounds the fractile on both sides")
    return dict(lines="\n".join(f"- {x}" for x in lines), n_groups=len(table), n_lognormal=supported, ranks=ranks,
                fractile=f"{100 * FRACTILE:g}", confidence=f"{100 * CONFIDENCE:g}")
