"""Statistics of a study's runs (docs/study.md, 11-12, 16): means, COVs,
brick shares and correlations per variant, level and failure mode, each
with a bootstrap interval.

A runs table has one row per simulation with at least: variant, the swept
level (its column: ``level``), sample, failure_mode, ok (the run reached
its stop criteria), P_max_kN, strength_mpa and the study's random inputs
(their columns: ``inputs``, as the study file names them, f_tj_mpa).  Runs
that are not ``ok`` (failed, or stopped before their peak was certain:
lower_bounds) are excluded from every statistic and counted.
``level`` (a Level: its column, name and unit) names the swept setting.
"""
import itertools
import warnings
from typing import NamedTuple

import numpy as np
import pandas as pd
from scipy.stats import DegenerateDataWarning, bootstrap


class Level(NamedTuple):
    """The swept setting: its column in the runs table, its name, the unit
    the column shows it in (plan.analysis: level_column, level, level_unit)."""
    column: str
    name: str
    unit: str

    def text(self, value):
        return f"{value:g} {self.unit}".rstrip()


def of_study(spec):
    """(Level, random inputs: column -> mean) of a study (plan.analysis)."""
    return (Level(spec["level_column"], spec["level"], spec["level_unit"]),
            {spec["columns"][name]: mean for name, mean in spec["means"].items()})


def check_one_solver(runs, level):
    """Refuse a runs table whose simulations come from different solver
    sources (column solver_version, 'version+source hash'; rows without one,
    runs that raised before the solver started, do not count).  Snakemake
    reruns a simulation when the solver's hash changes, but files marked up
    to date by hand (``--touch``) escape that; statistics over a mixture
    would compare two models.  Returns the version."""
    v = runs["solver_version"].dropna() if "solver_version" in runs else pd.Series(dtype=object)
    counts = v.value_counts()
    if len(counts) > 1:
        odd = runs[runs["solver_version"].isin(counts.index[1:])]
        names = ", ".join(f"{r['variant']}/{level.text(r[level.column])}/s{r['sample']} ({r['solver_version']})"
                          for _, r in odd.head(10).iterrows())
        raise ValueError(f"runs from {len(counts)} solver versions: {len(odd)} differ from {counts.index[0]} "
                         f"({counts.iloc[0]} runs): {names}{' ...' if len(odd) > 10 else ''}; rerun them "
                         f"(snakemake --forcerun <their result files>)")
    return counts.index[0] if len(counts) else None


LIMIT = "displacement_limit"     # the stop that ends a run without saying its peak was passed


def lower_bounds(runs, rate, window):
    """The runs table with each run whose peak is not certain marked as a
    lower bound: stopped by the displacement limit (status LIMIT) when its
    drive had moved less than ``window`` (m: the post-peak branch a row
    describes, specimen.protocol.DROP_WINDOW) past its peak, at ``rate``
    (m per step, the scene's drive), its load may still have been rising.
    Such a run gets status 'lower_bound' and is not ok (left out of every
    statistic, fit and fractile, and counted); its row is kept, with why."""
    travel = (runs.steps - runs.peak_step) * rate
    bound = runs.status.eq(LIMIT) & (travel < window)
    if not bound.any():
        return runs
    why = [f"{m}; the drive moved {1e3 * t:.3g} mm past the peak, less than the {1e3 * window:g} mm that make a "
           "peak certain: the strength is a lower bound" for m, t in zip(runs.message[bound], travel[bound])]
    out = runs.copy()
    out.loc[bound, "status"], out.loc[bound, "ok"], out.loc[bound, "message"] = "lower_bound", False, why
    return out


def _cov(x):
    x = np.asarray(x, float)
    return float(x.std(ddof=1) / x.mean()) if x.size > 1 else np.nan


def statistics(runs, level):
    """Mean, COV and count of P_max per variant, level and failure mode
    (mode 'all' for all modes together), with the share of brick failures
    and the number of runs excluded (not ok)."""
    rows = []
    for (variant, sv), g in runs.groupby(["variant", level.column]):
        good = g[g.ok]
        for mode in ("all", "joint", "brick"):
            sel = good if mode == "all" else good[good.failure_mode == mode]
            rows.append({"variant": variant, level.column: sv, "mode": mode, "count": len(sel),
                         "P_max_mean_kN": sel.P_max_kN.mean() if len(sel) else np.nan,
                         "P_max_cov": _cov(sel.P_max_kN),
                         "strength_mean_mpa": sel.strength_mpa.mean() if len(sel) else np.nan,
                         "brick_share": float((good.failure_mode == "brick").mean()) if len(good) else np.nan,
                         "excluded": int((~g.ok).sum())})
    return pd.DataFrame(rows)


def increase(stats, low, high, level):
    """Relative increase of the mean P_max from the level low to high, per
    variant and mode."""
    s = stats.set_index(["variant", "mode", level.column]).P_max_mean_kN
    out = []
    for (variant, mode), g in s.groupby(level=[0, 1]):
        g = g.droplevel([0, 1])
        if low in g.index and high in g.index:
            out.append(dict(variant=variant, mode=mode, increase=g[high] / g[low] - 1.0))
    return pd.DataFrame(out)


def running_mean(values):
    """Mean of the first k values, k = 1..n (is the sample large enough?)."""
    values = np.asarray(values, float)
    return np.cumsum(values) / np.arange(1, values.size + 1)


def correlations(runs, inputs, level):
    """Pearson correlation of P_max with each random input (its column),
    per variant, level and mode ('all' included)."""
    rows = []
    for (variant, sv), g in runs[runs.ok].groupby(["variant", level.column]):
        for mode in ("all", "joint", "brick"):
            sel = g if mode == "all" else g[g.failure_mode == mode]
            row = {"variant": variant, level.column: sv, "mode": mode, "count": len(sel)}
            for name in inputs:
                ok = len(sel) > 2 and sel[name].std() > 0 and sel.P_max_kN.std() > 0
                row[name] = float(np.corrcoef(sel[name], sel.P_max_kN)[0, 1]) if ok else np.nan
            rows.append(row)
    return pd.DataFrame(rows)


def correlation_band(n, z=1.96):
    """Half-width of the band around zero within which the Pearson
    correlation of n independent pairs falls with 95 % probability (z =
    1.96): z / sqrt(n - 1), the large-n standard deviation of r under
    independence."""
    return z / np.sqrt(n - 1.0)


def input_spread(runs, variant, inputs):
    """COV of each random input across a variant's samples (a sample's
    inputs are the same at every precompression level; for the spatial
    variant they are field means).  Empty dict if the variant has no run."""
    g = runs[runs.variant == variant].drop_duplicates("sample")
    return {n: _cov(g[n]) for n in inputs} if len(g) else {}


def normalised_deviation(x, mean):
    """(x - mean) / mean."""
    return (np.asarray(x, float) - mean) / mean


# --- confidence intervals (docs/study.md, 16) ----------------------------------------
CONFIDENCE = 0.95
MODES = ("all", "joint", "brick")


def bootstrap_interval(n, statistic, resamples, seed):
    """95 % percentile-bootstrap intervals (scipy.stats.bootstrap) of the
    vector ``statistic`` of n samples.  ``statistic(idx)`` takes sample
    indices, shape (batch, n), and returns an array (number of statistics,
    batch).  Whole samples are resampled, so a sample's runs at every
    precompression level, which share its properties, stay together.
    Returns (low, high); NaN where some resample leaves a statistic
    undefined (a failure mode with fewer than two runs, say)."""
    def stat(idx, axis=-1):
        return statistic(np.asarray(idx).reshape(-1, n))
    if n < 2:                                # nothing to resample
        nan = np.full(len(stat(np.arange(n))), np.nan)
        return nan, nan
    with np.errstate(invalid="ignore", divide="ignore"), warnings.catch_warnings():
        # a statistic constant over the resamples (a coefficient the Lasso
        # drops every time) has the interval [c, c]: not a degenerate case
        warnings.simplefilter("ignore", DegenerateDataWarning)
        ci = bootstrap((np.arange(n),), stat, n_resamples=resamples, confidence_level=CONFIDENCE,
                       method="percentile", vectorized=True, random_state=np.random.default_rng(seed)
                       ).confidence_interval
    return np.asarray(ci.low, float), np.asarray(ci.high, float)


def _wide(runs, variant, inputs, level):
    """A variant's runs as arrays over (sample, level): P_max, strength,
    the masks of the ok runs per mode of MODES (mode, sample, level) and
    the inputs (sample, level, input).  A run missing from the table
    counts as not ok.  Returns (levels, arrays)."""
    g = runs[runs.variant == variant]
    samples, levels = np.sort(g["sample"].unique()), np.sort(g[level.column].unique())
    w = g.set_index(["sample", level.column]).reindex(pd.MultiIndex.from_product([samples, levels]))
    shape = (samples.size, levels.size)
    ok = w.ok.fillna(False).to_numpy(bool).reshape(shape)
    mode = w.failure_mode.fillna("").to_numpy().reshape(shape)
    return levels, dict(P=w.P_max_kN.fillna(0.0).to_numpy(float).reshape(shape),
                        S=w.strength_mpa.fillna(0.0).to_numpy(float).reshape(shape),
                        M=np.stack([ok, ok & (mode == "joint"), ok & (mode == "brick")]),
                        X=np.stack([w[k].fillna(0.0).to_numpy(float).reshape(shape) for k in inputs], axis=-1))


@np.errstate(invalid="ignore", divide="ignore")              # a mode without runs: NaN
def _sample_statistics(d, idx):
    """The statistics of the samples ``idx`` (batch, n) of the arrays of
    ``_wide``: per mode and level the mean and COV of P_max, the mean
    strength and the Pearson correlation with each input; per level the
    brick share; per mode the increase from the first to the last level.
    Returns dict name -> array (batch, ...)."""
    P, S, X = d["P"][idx][:, None], d["S"][idx][:, None], d["X"][idx][:, None]   # (batch, 1, n, level[, input])
    M = np.moveaxis(d["M"][:, idx], 0, 1)                                       # (batch, mode, n, level)
    count = M.sum(2)
    mean = np.where(M, P, 0.0).sum(2) / count
    dev = np.where(M, P - mean[:, :, None], 0.0)
    xmean = np.where(M[..., None], X, 0.0).sum(2) / count[..., None]
    xdev = np.where(M[..., None], X - xmean[:, :, None], 0.0)
    r = (xdev * dev[..., None]).sum(2) / np.sqrt((xdev ** 2).sum(2) * (dev ** 2).sum(2)[..., None])
    return dict(mean=mean, cov=np.sqrt((dev ** 2).sum(2) / (count - 1)) / mean,
                strength=np.where(M, S, 0.0).sum(2) / count, share=count[:, 2] / count[:, 0], r=r,
                increase=mean[..., -1] / mean[..., 0] - 1.0)


def _flat(parts):
    """dict of arrays (batch, ...) -> one array (statistics, batch)."""
    return np.concatenate([a.reshape(a.shape[0], -1) for a in parts.values()], axis=1).T


def _unflat(vector, like):
    """The inverse of ``_flat`` for one batch: dict name -> array shaped as
    ``like``'s (without the batch axis)."""
    parts = np.split(vector, np.cumsum([a[0].size for a in like.values()])[:-1])
    return {name: v.reshape(a.shape[1:]) for (name, a), v in zip(like.items(), parts)}


def study_tables(runs, resamples, seed, inputs, level):
    """The tables of ``statistics``, ``correlations`` and ``increase`` (from
    the lowest level to the highest), each statistic with its 95 %
    bootstrap interval (``bootstrap_interval``, samples resampled within
    each variant) in the columns <column>_lo and <column>_hi."""
    stats, corr, inc = [], [], []
    for variant in sorted(runs.variant.unique()):
        levels, d = _wide(runs, variant, inputs, level)
        n = d["P"].shape[0]
        like = _sample_statistics(d, np.arange(n)[None])
        lo, hi = (_unflat(v, like) for v in bootstrap_interval(
            n, lambda idx: _flat(_sample_statistics(d, idx)), resamples, seed))
        for (i, mode), (j, sv) in itertools.product(enumerate(MODES), enumerate(levels)):
            key = {"variant": variant, level.column: sv, "mode": mode}
            stats.append(dict(key, P_max_mean_kN_lo=lo["mean"][i, j], P_max_mean_kN_hi=hi["mean"][i, j],
                              P_max_cov_lo=lo["cov"][i, j], P_max_cov_hi=hi["cov"][i, j],
                              strength_mean_mpa_lo=lo["strength"][i, j], strength_mean_mpa_hi=hi["strength"][i, j],
                              brick_share_lo=lo["share"][j], brick_share_hi=hi["share"][j]))
            corr.append(dict(key, **{f"{x}_{e}": b["r"][i, j, k] for k, x in enumerate(inputs)
                                     for e, b in (("lo", lo), ("hi", hi))}))
        inc += [dict(variant=variant, mode=mode, increase_lo=lo["increase"][i], increase_hi=hi["increase"][i])
                for i, mode in enumerate(MODES)]
    keys = ["variant", level.column, "mode"]
    st = statistics(runs, level).merge(pd.DataFrame(stats), on=keys, how="left")
    low, high = runs[level.column].min(), runs[level.column].max()
    return (st, correlations(runs, inputs, level).merge(pd.DataFrame(corr), on=keys, how="left"),
            increase(st, low, high, level).merge(pd.DataFrame(inc), how="left"))


# --- the prediction against the simulations and the design rules -------------------
def scatter_level(runs, level, near=None):
    """The level of the scatter plot: the one nearest ``near``, by default
    the middle of the levels' range."""
    levels = np.sort(runs[level.column].unique())
    near = (levels[0] + levels[-1]) / 2 if near is None else near
    return levels[np.argmin(np.abs(levels - near))]
