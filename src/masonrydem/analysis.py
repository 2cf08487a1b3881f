"""Analysis of the study's runs (docs/study.md, 11-14): statistics, correlations,
prediction equations and the design rules they are compared with.

A runs table has one row per simulation with at least: variant, sigma_v_mpa,
sample, failure_mode, ok (the run reached its stop criteria), P_max_kN,
strength_mpa and the random inputs f_tj_mpa, f_tu_mpa, phi_j_deg, E_b_mpa.
Runs that are not ``ok`` are excluded from every statistic and counted.
"""
import numpy as np
import pandas as pd
from sklearn.linear_model import LassoCV
from sklearn.model_selection import GroupKFold
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler

from .sampling import STUDY_VARIABLES

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


def fit_equation(f_tu, f_tj, sigma_v, strength, groups):
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
    the error to expect on a wallette the fit has not seen."""
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
    oof = np.empty_like(y)
    for train, test in GroupKFold(5).split(X, y, groups):
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


# --- design rules (docs/study.md, 14) -------------------------------------------------
def lourenco_gaetani(c_j, f_tu, overlap, unit_height):
    """Lower bounds of Lourenco & Gaetani: stepped (joint) failure
    f = c_j l_o / h_b; brick failure f = f_tu / 2 (MPa)."""
    return c_j * overlap / unit_height, 0.5 * f_tu


def as3700(f_mt, f_ut, f_d):
    """AS3700 horizontal bending at mean values (capacity factor 1,
    k_p = 1): stepped f = 2 sqrt(f_mt)(1 + f_d / f_mt), capped at
    4 sqrt(f_mt); line f = 0.44 f_ut + 0.56 f_mt (MPa)."""
    f_d = np.asarray(f_d, float)
    stepped = np.minimum(2.0 * np.sqrt(f_mt) * (1.0 + f_d / f_mt), 4.0 * np.sqrt(f_mt))
    line = np.full_like(f_d, 0.44 * f_ut + 0.56 * f_mt)
    return stepped, line


# --- the prediction against the simulations and the design rules -------------------
def scatter_level(runs, near=0.25):
    """The precompression level of the scatter plot: the one nearest ``near`` MPa."""
    levels = np.sort(runs.sigma_v_mpa.unique())
    return levels[np.argmin(np.abs(levels - near))]


def prediction_equations(ns):
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
        eq = fit_equation(g.f_tu_mpa, g.f_tj_mpa, g.sigma_v_mpa, g.strength_mpa, g["sample"])
        fits[mode] = (eq, g.strength_mpa.to_numpy())
        rows.append(dict(mode=mode, n=eq["n"], alpha=eq["alpha"], mape_pct=eq["mape"], cv_mape_pct=eq["cv_mape"],
                         intercept=eq["intercept"], **eq["coef"], equation=equation_text(eq)))
    resid_sd = np.nan
    if fits:
        low, low_mode = lower_of_two(*_pair(fits), ns.f_tu_mpa, ns.f_tj_mpa, ns.sigma_v_mpa)
        resid_sd = float(np.std(ns.strength_mpa - low, ddof=1))
        rows.append(dict(mode="lower of two", n=len(ns), mape_pct=mape(ns.strength_mpa, low),
                         mode_agreement=float(np.mean(low_mode == ns.failure_mode.to_numpy())),
                         residual_sd_mpa=resid_sd,
                         equation="min(joint, brick)" if len(fits) == 2 else f"the {next(iter(fits))} equation alone"))
    return fits, rows, resid_sd


def _pair(fits):
    """The joint and the brick equation; with one, it stands for both."""
    eqs = {m: e for m, (e, _) in fits.items()}
    return eqs.get("joint", eqs.get("brick")), eqs.get("brick", eqs.get("joint"))


def mean_strengths():
    """f_tu and f_tj (MPa) at the means of their distributions."""
    mean = {v.name: v.mean for v in STUDY_VARIABLES}
    return mean["f_tu"] / 1e6, mean["f_tj"] / 1e6


def wallette_geometry(scene):
    """What the design rules need of the scene (m): the overlap l_o = bond
    offset x modelled unit length, the height h_b of a modelled unit (unit +
    joint) and the joints' c_ratio (c_j = c_ratio f_tj)."""
    g, j = scene.geometry, scene.materials.joints
    return dict(l_o=g.bond_overlap, h_b=g.modelled_unit[2], c_ratio=j.c_ratio)


def design_table(fits, ns, resid_sd, levels, geometry):
    """Against the precompression ``levels``: the lower-of-two prediction
    at the mean properties with a band of one standard deviation, which
    combines the scatter of the prediction over the sampled properties
    (f_tu, f_tj of the samples of ``ns``) with the residual scatter the
    equations leave (phi_j, E_b and the misfit); the prediction's mean over
    the samples; the Lourenco-Gaetani and AS3700 rules at the mean
    properties (AS3700 f_mt from f_tj, the flexural bond ~ the joint's
    tensile bond, f_ut from f_tu).  NaN predictions without an equation."""
    f_tu, f_tj = mean_strengths()
    pred = band = prop_sd = prop_mean = np.full_like(levels, np.nan)
    if fits:
        joint, brick = _pair(fits)
        pred, _ = lower_of_two(joint, brick, np.full_like(levels, f_tu), np.full_like(levels, f_tj), levels)
        props = ns.drop_duplicates("sample")            # the properties of every sample with an ok run
        prop_mean, prop_sd = prediction_over_samples(joint, brick, props.f_tu_mpa, props.f_tj_mpa, levels)
        band = np.sqrt(prop_sd ** 2 + resid_sd ** 2)
    lg = lourenco_gaetani(geometry["c_ratio"] * f_tj, f_tu, geometry["l_o"], geometry["h_b"])
    as_stepped, as_line = as3700(f_tj, f_tu, levels)
    return pd.DataFrame(dict(sigma_v_mpa=levels, prediction=pred, band_sd=band, property_sd=prop_sd,
                             mean_over_samples=prop_mean, lg_stepped=lg[0], lg_brick=lg[1], as3700_stepped=as_stepped,
                             as3700_line=as_line))


def typical_run(runs, variant, mode):
    """The run to picture for a variant and failure mode: at the level where
    the mode is most frequent among the ok runs, the run nearest the
    median P_max of the mode there.  Returns (run, the mode's runs at that
    level), or (None, None) when no run failed in that mode."""
    group = runs[(runs.variant == variant) & (runs.failure_mode == mode) & runs.ok]
    if group.empty:
        return None, None
    sv = group.sigma_v_mpa.value_counts().sort_index().idxmax()
    at = group[group.sigma_v_mpa == sv]
    return at.iloc[(at.P_max_kN - at.P_max_kN.median()).abs().argmin()], at
