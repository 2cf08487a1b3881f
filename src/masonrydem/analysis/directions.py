"""Both bending directions of one study: the same samples run on the
horizontal and on the vertical wallette (a study file's ``directions``),
so that each sample's material gives a pair of strengths, f_x2
(horizontal bending, plane of failure perpendicular to the bed joints)
and f_x1 (vertical bending, parallel to them).

``paired`` joins the two runs tables on variant, sample and level, each
pair with both runs ok; ``mean_interval`` gives a mean with its exact
normal-theory interval (Student's t); ``ratio_interval`` the orthogonal
ratio mu = mean f_x1 / mean f_x2 from the pairs with Fieller's interval,
which allows for their correlation (the same material in both) and is
exact for bivariate normal pairs; ``directions_table`` both per level."""
import numpy as np
import pandas as pd
from scipy import stats

from ..errors import InputError

KEYS = ("variant", "sample")


def paired(horizontal, vertical, level_column):
    """The pairs of two runs tables (one per direction) with both runs ok:
    variant, sample, the level, f_x2 and f_x1 (MPa).  A sample whose run
    failed in either direction is no pair (its rows keep their status in
    each direction's own table)."""
    keys = [*KEYS, level_column]
    h = horizontal.loc[horizontal.ok, keys + ["strength_mpa"]].rename(columns={"strength_mpa": "f_x2"})
    v = vertical.loc[vertical.ok, keys + ["strength_mpa"]].rename(columns={"strength_mpa": "f_x1"})
    return h.merge(v, on=keys, how="inner", validate="one_to_one").sort_values(keys, ignore_index=True)


def mean_interval(x, conf=0.95):
    """(mean, low, high) of the mean of ``x``: Student's t interval, exact
    for a normal sample; NaN ends below two values."""
    x = np.asarray(x, float)
    m = float(np.mean(x)) if x.size else np.nan
    if x.size < 2:
        return m, np.nan, np.nan
    half = stats.t.ppf(0.5 + conf / 2, x.size - 1) * np.std(x, ddof=1) / np.sqrt(x.size)
    return m, m - half, m + half


def ratio_interval(x, y, conf=0.95):
    """(ratio, low, high): mean(x) / mean(y) of paired samples with
    Fieller's interval, the set of r for which mean(x) - r mean(y) = 0 is
    not rejected by the paired t test:
    (xb - r yb)^2 <= t^2 (s_xx - 2 r s_xy + r^2 s_yy) / n.  Where the
    denominator's mean is not clearly away from 0 the set is unbounded:
    NaN ends."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    n = x.size
    if n != y.size:
        raise InputError("pairs", f"{n} values of one direction against {y.size} of the other")
    if n < 2:
        return (float(np.mean(x) / np.mean(y)) if n else np.nan), np.nan, np.nan
    xb, yb = x.mean(), y.mean()
    c = np.cov(x, y, ddof=1)
    t2 = stats.t.ppf(0.5 + conf / 2, n - 1) ** 2 / n
    a = yb * yb - t2 * c[1, 1]
    b = xb * yb - t2 * c[0, 1]
    cc = xb * xb - t2 * c[0, 0]
    disc = b * b - a * cc
    if a <= 0 or disc < 0:
        return float(xb / yb), np.nan, np.nan
    root = np.sqrt(disc)
    return float(xb / yb), float((b - root) / a), float((b + root) / a)


def directions_table(pairs, level_column, conf=0.95):
    """Per variant and level: the pairs' count, f_x2 and f_x1 with their
    mean's interval, and mu = f_x1 / f_x2 (ratio of the means) with
    Fieller's interval."""
    rows = []
    for (variant, level), g in pairs.groupby(["variant", level_column], sort=True):
        f2, f1 = mean_interval(g.f_x2, conf), mean_interval(g.f_x1, conf)
        mu = ratio_interval(g.f_x1, g.f_x2, conf)
        rows.append({"variant": variant, level_column: level, "pairs": len(g),
                     "f_x2_mpa": f2[0], "f_x2_low": f2[1], "f_x2_high": f2[2],
                     "f_x1_mpa": f1[0], "f_x1_low": f1[1], "f_x1_high": f1[2],
                     "mu": mu[0], "mu_low": mu[1], "mu_high": mu[2],
                     "pair_correlation": float(np.corrcoef(g.f_x1, g.f_x2)[0, 1]) if len(g) > 2 else np.nan})
    return pd.DataFrame(rows)
