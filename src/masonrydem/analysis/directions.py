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
from . import fractiles
from .design import FXK1_CLAY, FXK2_CLAY
from .statistics import Level
from .validation import as3700, as3700_vertical

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


def with_codes(table, runs, level_column, f_mt, f_ut, mortar):
    """The directions table with the codes beside it, for the study's
    units at its mean bond ``f_mt`` and units' strength ``f_ut`` (MPa) and
    EN 1996-1-1's mortar column ``mortar`` (design.FXK1_CLAY's keys):
    EN 1996-1-1's recommended f_xk1 (apparent, f_xk1 + sigma_d, 6.3.1)
    and f_xk2 against each direction's characteristic strength (the 5 %
    fractile of its runs, fractiles.characteristic_table), and AS 3700's
    vertical and horizontal rules at mean values against each direction's
    mean; each as the simulated-to-code ratio.  ``runs``: direction ->
    its runs table (pairs only, as ``paired`` gives them: f_x1, f_x2)."""
    if mortar not in FXK1_CLAY:
        raise InputError("directions.mortar", f"{mortar!r} is not a mortar of EN 1996-1-1's tables; one of: "
                         f"{', '.join(FXK1_CLAY)}")
    level = Level(level_column, level_column, "MPa")
    k = {}
    for name, col in (("f_x1", "f_x1"), ("f_x2", "f_x2")):
        t = fractiles.characteristic_table(runs.assign(strength_mpa=runs[col], ok=True), level)
        k[name] = t.set_index(["variant", level_column]).characteristic_mpa
    key = pd.MultiIndex.from_frame(table[["variant", level_column]])
    sigma = table[level_column].to_numpy(float)
    stepped, line = as3700(f_mt, f_ut, sigma)
    out = table.assign(
        f_x1_k_mpa=k["f_x1"].reindex(key).to_numpy(), f_x2_k_mpa=k["f_x2"].reindex(key).to_numpy(),
        en_fxk1_app_mpa=FXK1_CLAY[mortar] + sigma, en_fxk2_mpa=FXK2_CLAY[mortar],
        as3700_vertical_mpa=as3700_vertical(f_mt, sigma), as3700_horizontal_mpa=np.minimum(stepped, line))
    return out.assign(f_x1_k_over_en=out.f_x1_k_mpa / out.en_fxk1_app_mpa,
                      f_x2_k_over_en=out.f_x2_k_mpa / out.en_fxk2_mpa,
                      f_x1_over_as3700=out.f_x1_mpa / out.as3700_vertical_mpa,
                      f_x2_over_as3700=out.f_x2_mpa / out.as3700_horizontal_mpa)


def placed(tests, runs, level_column, tol=1e-9):
    """The user's wallette tests (labsheet.read_sheet of a wallette sheet:
    ``tests`` with direction, level in Pa and strength in Pa per test) in
    the simulated distribution of their direction and level (``runs``:
    direction -> its runs table, ok runs of the variant compared).  Per
    test: the runs at its level, how many lie below it (ties count half),
    and its predicted percentile (below + 0.5) / (runs + 1).  Refused: a
    test at a level or in a direction the study did not run."""
    rows = []
    for i, (direction, level, x) in enumerate(zip(tests["directions"], tests["levels"], tests["values"])):
        where = f"{tests['name']} row {tests['rows'][i]}"
        if direction not in runs:
            raise InputError(where, f"a test in {direction} bending, which the study did not run (its directions: "
                                    f"{', '.join(runs)})")
        r = runs[direction]
        at = r[np.isclose(r[level_column], level / 1e6, rtol=0, atol=tol)].strength_mpa.to_numpy(float)
        if at.size == 0:
            raise InputError(where, f"a test at {level / 1e6:g} MPa precompression, a level the study did not run "
                                    f"(its levels: {', '.join(f'{v:g}' for v in sorted(r[level_column].unique()))} MPa)")
        below = float(np.sum(at < x / 1e6) + 0.5 * np.sum(at == x / 1e6))
        rows.append({"row": tests["rows"][i], "direction": direction, level_column: level / 1e6,
                     "strength_mpa": x / 1e6, "runs": at.size, "runs_below": below,
                     "percentile": (below + 0.5) / (at.size + 1), "simulated_mean_mpa": float(at.mean())})
    return pd.DataFrame(rows)


def u_distribution(n, m):
    """The exact null distribution of the Mann-Whitney count U (how many of
    m runs lie below each of n tests, summed) when tests and runs are
    draws of one distribution: P(U = u), u = 0..n m, by the recurrence on
    the largest of all n + m values (a test, adding m, or a run)."""
    table = {(k, 0): np.ones(1) for k in range(n + 1)}      # k tests among j runs -> counts of U
    for j in range(1, m + 1):
        table[(0, j)] = np.ones(1)
        for k in range(1, n + 1):
            out = np.zeros(k * j + 1)
            out[j:] += table[(k - 1, j)]          # the largest a test: j runs below it
            out[:k * (j - 1) + 1] += table[(k, j - 1)]     # the largest a run
            table[(k, j)] = out
    d = table[(n, m)]
    return d / d.sum()


def agreement(table, level_column):
    """The tests' agreement with the prediction: under it each test is one
    more draw of its direction's and level's distribution.  Per direction
    and level the count of runs below the tests (ties half) is the
    Mann-Whitney U of that stratum, whose exact null distribution
    (``u_distribution``) allows for the tests sharing its runs; the strata
    are independent, so their sum has the convolution as its exact
    distribution.  Returns (the sum, its mean under the prediction, the
    two-sided p-value: tests systematically above or below the runs)."""
    dist = np.array([1.0])
    strata = table.groupby(["direction", level_column])
    for _, g in strata:
        dist = np.convolve(dist, u_distribution(len(g), int(g.runs.iloc[0])))
    u = float(table.runs_below.sum())
    lower, upper = dist[:int(np.floor(u)) + 1].sum(), dist[int(np.ceil(u)):].sum()
    mean = float(sum(len(g) * g.runs.iloc[0] for _, g in strata) / 2)
    return u, mean, float(min(1.0, 2 * min(lower, upper)))
