"""Analysis of the study's runs (docs/study.md, 11-14): statistics, correlations,
prediction equations and the design rules they are compared with.

A runs table has one row per simulation with at least: variant, sigma_v_mpa,
sample, failure_mode, ok (the run reached its stop criteria), P_max_kN,
strength_mpa and the random inputs f_tj_mpa, f_tu_mpa, phi_j_deg, E_b_mpa.
Runs that are not ``ok`` are excluded from every statistic and counted.
"""
import itertools
import warnings

import numpy as np
import pandas as pd
from scipy.stats import DegenerateDataWarning, bootstrap
from sklearn.linear_model import LassoCV
from sklearn.model_selection import GroupKFold
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from .sampling import STUDY_VARIABLES

ANALYSIS_ONLY = True     # not in the solver's source hash (masonrydem.simulation_sources)

INPUTS = ("f_tj_mpa", "f_tu_mpa", "phi_j_deg", "E_b_mpa")
# the means of their distributions (docs/study.md, 6) in the units of the runs table
_COLUMN = {"f_tj": ("f_tj_mpa", 1e-6), "f_tu": ("f_tu_mpa", 1e-6), "phi_j": ("phi_j_deg", 1.0), "E_b": ("E_b_mpa", 1e-6)}
INPUT_MEANS = {_COLUMN[v.name][0]: v.mean * _COLUMN[v.name][1] for v in STUDY_VARIABLES}
FEATURES = ("f_tu", "f_tj", "f_tu^2", "f_tj^2", "sigma_v")


def check_one_solver(runs):
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
        names = ", ".join(f"{r.variant}/sv{r.sigma_v_mpa:g}/s{r.sample} ({r.solver_version})"
                          for r in odd.head(10).itertuples())
        raise ValueError(f"runs from {len(counts)} solver versions: {len(odd)} differ from {counts.index[0]} "
                         f"({counts.iloc[0]} runs): {names}{' ...' if len(odd) > 10 else ''}; rerun them "
                         f"(snakemake --forcerun <their result files>)")
    return counts.index[0] if len(counts) else None


def _cov(x):
    x = np.asarray(x, float)
    return float(x.std(ddof=1) / x.mean()) if x.size > 1 else np.nan


def statistics(runs):
    """Mean, COV and count of P_max per variant, sigma_v and failure mode
    (mode 'all' for all modes together), with the share of brick failures
    and the number of runs excluded (not ok)."""
    rows = []
    for (variant, sv), g in runs.groupby(["variant", "sigma_v_mpa"]):
        good = g[g.ok]
        for mode in ("all", "joint", "brick"):
            sel = good if mode == "all" else good[good.failure_mode == mode]
            rows.append(dict(variant=variant, sigma_v_mpa=sv, mode=mode, count=len(sel),
                             P_max_mean_kN=sel.P_max_kN.mean() if len(sel) else np.nan,
                             P_max_cov=_cov(sel.P_max_kN),
                             strength_mean_mpa=sel.strength_mpa.mean() if len(sel) else np.nan,
                             brick_share=float((good.failure_mode == "brick").mean()) if len(good) else np.nan,
                             excluded=int((~g.ok).sum())))
    return pd.DataFrame(rows)


def increase(stats, low=0.0, high=0.5):
    """Relative increase of the mean P_max from sigma_v = low to high, per
    variant and mode."""
    s = stats.set_index(["variant", "mode", "sigma_v_mpa"]).P_max_mean_kN
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


def correlations(runs, inputs=INPUTS):
    """Pearson correlation of P_max with each random input, per variant,
    sigma_v and mode ('all' included)."""
    rows = []
    for (variant, sv), g in runs[runs.ok].groupby(["variant", "sigma_v_mpa"]):
        for mode in ("all", "joint", "brick"):
            sel = g if mode == "all" else g[g.failure_mode == mode]
            row = dict(variant=variant, sigma_v_mpa=sv, mode=mode, count=len(sel))
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


def input_spread(runs, variant, inputs=INPUTS):
    """COV of each random input across a variant's samples (a sample's
    inputs are the same at every precompression level; for the spatial
    variant they are field means).  Empty dict if the variant has no run."""
    g = runs[runs.variant == variant].drop_duplicates("sample")
    return {n: _cov(g[n]) for n in inputs} if len(g) else {}


def normalised_deviation(x, mean):
    """(x - mean) / mean."""
    return (np.asarray(x, float) - mean) / mean


# --- prediction equations -------------------------------------------------------
def features(f_tu, f_tj, sigma_v):
    """Feature matrix (f_tu, f_tj, f_tu^2, f_tj^2, sigma_v), MPa."""
    f_tu, f_tj, sigma_v = (np.asarray(a, float) for a in (f_tu, f_tj, sigma_v))
    return np.column_stack([f_tu, f_tj, f_tu ** 2, f_tj ** 2, sigma_v])


MIN_GROUPS = 7   # nested 5-fold CV: each inner fit needs 5 groups of the outer 4/5


def _lasso(X, y, groups):
    """Standardised features, Lasso with the penalty chosen by 5-fold
    cross-validation on the MSE, folds made of whole groups.  Coordinate
    descent to a duality gap of 1e-10 (scikit-learn's default, 1e-4, left
    the study's coefficients up to 8 % from the optimum at the chosen
    penalty, f_tu and f_tu^2 being nearly collinear: tests/test_regression.py
    checks the optimality conditions)."""
    cv = list(GroupKFold(5).split(X, y, groups))
    return make_pipeline(StandardScaler(), LassoCV(cv=cv, max_iter=1_000_000, tol=1e-10)).fit(X, y)


def fit_equation(f_tu, f_tj, sigma_v, strength, groups, nested=True):
    """Lasso regression of the strength (MPa) on the features, the penalty
    chosen by 5-fold cross-validation on the mean squared error
    (scikit-learn LassoCV, features standardised).  ``groups``: the sample
    of each run; folds hold whole samples, because one sample's runs at
    the other precompression levels share its properties and would let a
    fold see the wallette it is tested on.  At least MIN_GROUPS samples.

    Returns a dict with the intercept and coefficients in original units,
    the chosen alpha, the fitted values and their MAPE (%), and the
    out-of-fold predictions and their MAPE (``cv_mape``): each run
    predicted by the equation fitted, penalty chosen included, on the
    other four fifths of the samples (nested cross-validation), which is
    the error to expect on a wallette the fit has not seen (left out,
    NaN, with ``nested=False``)."""
    X = features(f_tu, f_tj, sigma_v)
    y = np.asarray(strength, float)
    groups = np.asarray(groups)
    if np.unique(groups).size < MIN_GROUPS:
        raise ValueError(f"{np.unique(groups).size} samples: nested 5-fold CV needs at least {MIN_GROUPS}")
    fit = _lasso(X, y, groups)
    scaler, lasso = fit[0], fit[1]
    coef = lasso.coef_ / scaler.scale_
    intercept = float(lasso.intercept_ - np.sum(coef * scaler.mean_))
    fitted = fit.predict(X)
    oof = np.full_like(y, np.nan)
    for train, test in GroupKFold(5).split(X, y, groups) if nested else ():
        oof[test] = _lasso(X[train], y[train], groups[train]).predict(X[test])
    return dict(intercept=intercept, coef=dict(zip(FEATURES, (coef + 0.0).tolist())), alpha=float(lasso.alpha_),
                mape=mape(y, fitted), fitted=fitted, cv_mape=mape(y, oof), cv_predicted=oof, n=int(y.size))


def predict(eq, f_tu, f_tj, sigma_v):
    return eq["intercept"] + features(f_tu, f_tj, sigma_v) @ np.array([eq["coef"][k] for k in FEATURES])


def mape(y, yhat):
    """Mean absolute percentage error (%)."""
    y, yhat = np.asarray(y, float), np.asarray(yhat, float)
    return float(100.0 * np.mean(np.abs((yhat - y) / y)))


def equation_text(eq):
    terms = " ".join(f"{'+' if c >= 0 else '-'} {abs(c):.4g} {k}" for k, c in eq["coef"].items() if c != 0)
    return f"sigma = {eq['intercept']:.4g} {terms}  (MPa)"


def lower_of_two(eq_joint, eq_brick, f_tu, f_tj, sigma_v):
    """Predicted capacity: the lower of the two equations; the predicted
    mode is that of the lower one.  Returns (strength, mode array)."""
    j = predict(eq_joint, f_tu, f_tj, sigma_v)
    b = predict(eq_brick, f_tu, f_tj, sigma_v)
    return np.minimum(j, b), np.where(j <= b, "joint", "brick")


def prediction_over_samples(eq_joint, eq_brick, f_tu, f_tj, levels):
    """Mean and standard deviation, at each precompression of ``levels``,
    of the lower-of-two prediction over the property samples (f_tu, f_tj).
    The standard deviation is the scatter of the capacity that the scatter
    of the strengths causes, through the equations.  The mean is the mean
    capacity; it lies at or below the prediction at the mean properties,
    because the lower of two linear functions is concave (Jensen's
    inequality), most where the two equations cross."""
    f_tu, f_tj = np.asarray(f_tu, float), np.asarray(f_tj, float)
    low = np.array([lower_of_two(eq_joint, eq_brick, f_tu, f_tj, np.full_like(f_tu, sv))[0] for sv in levels])
    return low.mean(axis=1), low.std(axis=1, ddof=1)


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


def _wide(runs, variant, inputs):
    """A variant's runs as arrays over (sample, level): P_max, strength,
    the masks of the ok runs per mode of MODES (mode, sample, level) and
    the inputs (sample, level, input).  A run missing from the table
    counts as not ok.  Returns (levels, arrays)."""
    g = runs[runs.variant == variant]
    samples, levels = np.sort(g["sample"].unique()), np.sort(g.sigma_v_mpa.unique())
    w = g.set_index(["sample", "sigma_v_mpa"]).reindex(pd.MultiIndex.from_product([samples, levels]))
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


def study_tables(runs, resamples, seed, inputs=INPUTS):
    """The tables of ``statistics``, ``correlations`` and ``increase`` (from
    the lowest level to the highest), each statistic with its 95 %
    bootstrap interval (``bootstrap_interval``, samples resampled within
    each variant) in the columns <column>_lo and <column>_hi."""
    stats, corr, inc = [], [], []
    for variant in sorted(runs.variant.unique()):
        levels, d = _wide(runs, variant, inputs)
        n = d["P"].shape[0]
        like = _sample_statistics(d, np.arange(n)[None])
        lo, hi = (_unflat(v, like) for v in bootstrap_interval(
            n, lambda idx: _flat(_sample_statistics(d, idx)), resamples, seed))
        for (i, mode), (j, sv) in itertools.product(enumerate(MODES), enumerate(levels)):
            key = dict(variant=variant, sigma_v_mpa=sv, mode=mode)
            stats.append(dict(key, P_max_mean_kN_lo=lo["mean"][i, j], P_max_mean_kN_hi=hi["mean"][i, j],
                              P_max_cov_lo=lo["cov"][i, j], P_max_cov_hi=hi["cov"][i, j],
                              strength_mean_mpa_lo=lo["strength"][i, j], strength_mean_mpa_hi=hi["strength"][i, j],
                              brick_share_lo=lo["share"][j], brick_share_hi=hi["share"][j]))
            corr.append(dict(key, **{f"{x}_{e}": b["r"][i, j, k] for k, x in enumerate(inputs)
                                     for e, b in (("lo", lo), ("hi", hi))}))
        inc += [dict(variant=variant, mode=mode, increase_lo=lo["increase"][i], increase_hi=hi["increase"][i])
                for i, mode in enumerate(MODES)]
    keys = ["variant", "sigma_v_mpa", "mode"]
    st = statistics(runs).merge(pd.DataFrame(stats), on=keys, how="left")
    return (st, correlations(runs, inputs).merge(pd.DataFrame(corr), on=keys, how="left"),
            increase(st, runs.sigma_v_mpa.min(), runs.sigma_v_mpa.max()).merge(pd.DataFrame(inc), how="left"))


EQUATION_TERMS = ("intercept",) + FEATURES + ("mape_pct",)


def equation_intervals(ns, resamples, seed, progress=None):
    """95 % bootstrap intervals (``bootstrap_interval``, whole samples
    resampled) of the prediction equations of ``prediction_equations``:
    per mode the intercept, the coefficients and the MAPE of the fit
    (each resample refits, penalty chosen by cross-validation included;
    the nested cross-validation is left out), and the lower-of-two MAPE.
    NaN where a resample leaves a mode too few samples to fit.  Returns a
    frame with the column mode and <term>_lo, <term>_hi."""
    samples = np.sort(ns["sample"].unique())
    by_sample = [ns[ns["sample"] == s] for s in samples]

    def one(idx):
        fits, rows, _ = prediction_equations(pd.concat([by_sample[i] for i in idx]), nested=False)
        rows = {r["mode"]: r for r in rows}
        return [rows.get(m, {}).get(t, np.nan) for m in ("joint", "brick") for t in EQUATION_TERMS] + \
            [rows.get("lower of two", {}).get("mape_pct", np.nan)]

    def statistic(idx):
        out = []
        for k, i in enumerate(idx):
            out.append(one(i))
            if progress and (k + 1) % 100 == 0:
                progress(k + 1, len(idx))
        return np.array(out, float).T
    lo, hi = bootstrap_interval(samples.size, statistic, resamples, seed)
    n = len(EQUATION_TERMS)
    rows = [dict(mode=m, **{f"{t}_{e}": b[k * n + j] for j, t in enumerate(EQUATION_TERMS)
                            for e, b in (("lo", lo), ("hi", hi))}) for k, m in enumerate(("joint", "brick"))]
    return pd.DataFrame(rows + [dict(mode="lower of two", mape_pct_lo=lo[-1], mape_pct_hi=hi[-1])])


# --- the prediction against the simulations and the design rules -------------------
def scatter_level(runs, near=0.25):
    """The precompression level of the scatter plot: the one nearest ``near`` MPa."""
    levels = np.sort(runs.sigma_v_mpa.unique())
    return levels[np.argmin(np.abs(levels - near))]


def prediction_equations(ns, nested=True):
    """Per failure mode, the equation fitted to the runs ``ns`` (the ok
    non-spatial runs) when they span MIN_GROUPS samples; then the
    predictor, the lower of the two (with one equation it stands for both),
    scored on every run of ``ns``.  Returns (fits, rows, residual_sd):
    mode -> (equation, simulated strengths); the equations table's rows;
    the standard deviation of the predictor's residuals (MPa)."""
    fits, rows = {}, []
    for mode in ("joint", "brick"):
        g = ns[ns.failure_mode == mode]
        if g["sample"].nunique() < MIN_GROUPS:
            rows.append(dict(mode=mode, n=len(g), equation=f"too few runs to fit ({g['sample'].nunique()} samples, "
                                                              f"the nested 5-fold CV needs {MIN_GROUPS})"))
            continue
        eq = fit_equation(g.f_tu_mpa, g.f_tj_mpa, g.sigma_v_mpa, g.strength_mpa, g["sample"], nested=nested)
        fits[mode] = (eq, g.strength_mpa.to_numpy())
        rows.append(dict(mode=mode, n=eq["n"], alpha=eq["alpha"], mape_pct=eq["mape"], cv_mape_pct=eq["cv_mape"],
                         intercept=eq["intercept"], **eq["coef"], equation=equation_text(eq)))
    resid_sd = np.nan
    if fits:
        low, low_mode = lower_of_two(*joint_and_brick(fits), ns.f_tu_mpa, ns.f_tj_mpa, ns.sigma_v_mpa)
        resid_sd = float(np.std(ns.strength_mpa - low, ddof=1))
        rows.append(dict(mode="lower of two", n=len(ns), mape_pct=mape(ns.strength_mpa, low),
                         mode_agreement=float(np.mean(low_mode == ns.failure_mode.to_numpy())),
                         residual_sd_mpa=resid_sd,
                         equation="min(joint, brick)" if len(fits) == 2 else f"the {next(iter(fits))} equation alone"))
    return fits, rows, resid_sd


def joint_and_brick(fits):
    """The joint and the brick equation; with one, it stands for both."""
    eqs = {m: e for m, (e, _) in fits.items()}
    return eqs.get("joint", eqs.get("brick")), eqs.get("brick", eqs.get("joint"))


def mean_strengths():
    """f_tu and f_tj (MPa) at the means of their distributions."""
    mean = {v.name: v.mean for v in STUDY_VARIABLES}
    return mean["f_tu"] / 1e6, mean["f_tj"] / 1e6
