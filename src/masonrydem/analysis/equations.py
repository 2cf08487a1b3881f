"""The study's prediction equations (docs/study.md, 13): Lasso regressions
of the strength on terms of the study's inputs, one per failure mode, and
the lower of the two as the predictor.

An equation's terms are named as a study file's regression names them
(study/terms.py): an input (a random variable, or the swept setting
by its name), a power of one ('f_tu^2'), a product ('f_tj*sigma_v') or any
arithmetic expression of inputs ('f_tj*(L + t)/(H + t)'), each input in the
unit the runs table shows it in (MPa, mm, deg).
``inputs`` below is a mapping input -> values; ``inputs_of`` takes it from
a runs table by the study's columns (Study.columns).  An equation is a
dict with its intercept and coef (term -> coefficient, in the order of the
terms): it carries its own terms.
"""
from typing import NamedTuple

import numpy as np
import pandas as pd
from sklearn import config_context
from sklearn.linear_model import lars_path
from sklearn.model_selection import GroupKFold
from sklearn.preprocessing import StandardScaler

from ..study.terms import MIN_SAMPLES, evaluate_term


def inputs_of(runs, columns):
    """Input -> its values (float array) in the runs table ``runs``."""
    return {name: runs[col].to_numpy(float) for name, col in columns.items() if col in runs}


def features(inputs, terms):
    """The matrix of the ``terms`` (one column each) over ``inputs``."""
    inputs = {k: np.asarray(v, float) for k, v in inputs.items()}
    columns = [np.asarray(evaluate_term(term, inputs), float) for term in terms]
    return np.column_stack(np.broadcast_arrays(*columns))


class LassoFit(NamedTuple):
    """A Lasso on standardised features: the scaler, the coefficients of
    the standardised features, the intercept, the penalty."""
    scaler: StandardScaler
    coef: np.ndarray
    intercept: float
    alpha: float

    def predict(self, X):
        return self.scaler.transform(X) @ self.coef + self.intercept


def _path(Z, y, alphas):
    """The Lasso's exact coefficients at ``alphas``, intercept free: the
    LARS-Lasso path of the centred data (scikit-learn lars_path; Efron et
    al. 2004), linear in alpha between its breakpoints.  Returns (coefs
    (p, len(alphas)), intercepts)."""
    zm, ym = Z.mean(axis=0), y.mean()
    with config_context(skip_parameter_validation=True):        # 3 ms a call, most of the path's time
        knots, _, path = lars_path(Z - zm, y - ym, method="lasso")
    # a variable that leaves the active set keeps round-off at its knot
    # (-8.7e-19 on the study's brick runs): zero there, as on its segment
    path[np.abs(path) < 1e-13 * np.abs(path).max(initial=0.0)] = 0.0
    coefs = np.array([np.interp(alphas, knots[::-1], row[::-1]) for row in path])
    return coefs, ym - zm @ coefs


def _lasso(X, y, groups, n_alphas=100, eps=1e-3):
    """Standardised features, Lasso with the penalty chosen by 5-fold
    cross-validation on the MSE, folds made of whole groups: scikit-learn
    LassoCV's choice (its grid of ``n_alphas`` penalties from the largest
    useful one down to ``eps`` times it, the MSE averaged over the folds,
    the first smallest), each fit being the exact solution on the LARS
    path rather than coordinate descent.  Coordinate descent needed a
    duality gap of 1e-10 (scikit-learn's default, 1e-4, left the study's
    coefficients up to about 9 % from the optimum, f_tu and f_tu^2 being nearly
    collinear) and took about 0.5 s a fit; the path, a few milliseconds
    (tests/test_regression.py: the optimality conditions, and LassoCV's
    choice)."""
    scaler = StandardScaler().fit(X)
    Z = scaler.transform(X)
    yc = y - y.mean()
    top = np.max(np.abs(Z.T @ yc - Z.mean(axis=0) * np.sum(yc))) / len(y)
    alphas = np.geomspace(top, top * eps, num=n_alphas)
    mse = []
    for train, test in GroupKFold(5).split(X, y, groups):
        coefs, b0 = _path(Z[train], y[train], alphas)
        mse.append(np.mean((Z[test] @ coefs + b0 - y[test][:, None]) ** 2, axis=0))
    best = int(np.argmin(np.mean(mse, axis=0)))
    coef, b0 = _path(Z, y, alphas[best:best + 1])
    return LassoFit(scaler, coef[:, 0], float(b0[0]), float(alphas[best]))


def fit_equation(inputs, strength, groups, terms, nested=True):
    """Lasso regression of the strength (MPa) on the ``terms`` of the
    ``inputs``, the penalty chosen by 5-fold cross-validation on the mean
    squared error (LassoCV's choice, features standardised: ``_lasso``).
    ``groups``: the sample of each run; folds hold whole samples, because
    one sample's runs at the other levels share its properties and would
    let a fold see the wallette it is tested on.  At least MIN_SAMPLES
    samples.

    Returns a dict with the intercept and coefficients in original units,
    the chosen alpha, the fitted values and their MAPE (%), and the
    out-of-fold predictions and their MAPE (``cv_mape``): each run
    predicted by the equation fitted, penalty chosen included, on the
    other four fifths of the samples (nested cross-validation), which is
    the error to expect on a wallette the fit has not seen (left out,
    NaN, with ``nested=False``)."""
    return fit_features(features(inputs, terms), strength, groups, terms, nested)


def fit_features(X, strength, groups, terms, nested=True):
    """fit_equation on the matrix X of the ``terms`` (``features``)."""
    y = np.asarray(strength, float)
    groups = np.asarray(groups)
    if np.unique(groups).size < MIN_SAMPLES:
        raise ValueError(f"{np.unique(groups).size} samples: nested 5-fold CV needs at least {MIN_SAMPLES}")
    fit = _lasso(X, y, groups)
    coef = fit.coef / fit.scaler.scale_
    intercept = float(fit.intercept - np.sum(coef * fit.scaler.mean_))
    fitted = fit.predict(X)
    oof = np.full_like(y, np.nan)
    for train, test in GroupKFold(5).split(X, y, groups) if nested else ():
        oof[test] = _lasso(X[train], y[train], groups[train]).predict(X[test])
    return dict(intercept=intercept, coef=dict(zip(terms, (coef + 0.0).tolist())), alpha=fit.alpha,
                mape=mape(y, fitted), fitted=fitted, cv_mape=mape(y, oof), cv_predicted=oof, n=int(y.size))


def predict(eq, inputs):
    """The equation ``eq`` at ``inputs`` (its terms' inputs at least)."""
    return on_features(eq, features(inputs, tuple(eq["coef"])))


def on_features(eq, X):
    """The equation ``eq`` on the matrix X of its terms (``features``)."""
    return eq["intercept"] + X @ np.array(list(eq["coef"].values()))


def mape(y, yhat):
    """Mean absolute percentage error (%)."""
    y, yhat = np.asarray(y, float), np.asarray(yhat, float)
    return float(100.0 * np.mean(np.abs((yhat - y) / y)))


def equation_text(eq):
    terms = " ".join(f"{'+' if c >= 0 else '-'} {abs(c):.4g} {k}" for k, c in eq["coef"].items() if c != 0)
    return f"sigma = {eq['intercept']:.4g} {terms}  (MPa)"


def lower_of_two(eq_joint, eq_brick, inputs):
    """Predicted capacity: the lower of the two equations; the predicted
    mode is that of the lower one.  Returns (strength, mode array)."""
    return _lower(predict(eq_joint, inputs), predict(eq_brick, inputs))


def _lower(joint, brick):
    """The lower of the joint and the brick equation's values, and its mode."""
    return np.minimum(joint, brick), np.where(joint <= brick, "joint", "brick")


def prediction_over_samples(eq_joint, eq_brick, samples, level, levels):
    """Mean and standard deviation, at each of the ``levels`` of the input
    ``level`` (the sweep), of the lower-of-two prediction over the property
    samples ``samples`` (input -> values).  The standard deviation is the
    scatter of the capacity that the scatter of the properties causes,
    through the equations.  The mean is the mean capacity; it lies at or
    below the prediction at the mean properties, because the lower of two
    linear functions is concave (Jensen's inequality), most where the two
    equations cross."""
    n = len(next(iter(samples.values())))
    low = np.array([lower_of_two(eq_joint, eq_brick, {**samples, level: np.full(n, float(x))})[0] for x in levels])
    return low.mean(axis=1), low.std(axis=1, ddof=1)


def prediction_equations(ns, terms, columns, nested=True):
    """Per failure mode, the equation fitted to the runs ``ns`` (the ok runs
    of the study's regression variant) when they span MIN_SAMPLES samples; then the
    predictor, the lower of the two (with one equation it stands for both),
    scored on every run of ``ns``.  Returns (fits, rows, residual_sd):
    mode -> (equation, simulated strengths); the equations table's rows;
    the standard deviation of the predictor's residuals (MPa)."""
    return _equations(*_arrays(ns, terms, columns), terms, nested)


def _arrays(ns, terms, columns):
    """The runs ``ns`` as arrays: the matrix of the terms, the strength, the
    failure mode and the sample of each run."""
    return (features(inputs_of(ns, columns), terms), ns.strength_mpa.to_numpy(float), ns.failure_mode.to_numpy(),
            ns["sample"].to_numpy())


def _equations(X, y, mode, sample, terms, nested):
    """prediction_equations on the runs as arrays (``_arrays``)."""
    fits, rows = {}, []
    for m in ("joint", "brick"):
        k = mode == m
        if np.unique(sample[k]).size < MIN_SAMPLES:
            rows.append(dict(mode=m, n=int(k.sum()), equation=f"too few runs to fit ({np.unique(sample[k]).size} "
                                                                f"samples, the nested 5-fold CV needs {MIN_SAMPLES})"))
            continue
        eq = fit_features(X[k], y[k], sample[k], terms, nested=nested)
        fits[m] = (eq, y[k])
        rows.append(dict(mode=m, n=eq["n"], alpha=eq["alpha"], mape_pct=eq["mape"], cv_mape_pct=eq["cv_mape"],
                         intercept=eq["intercept"], **eq["coef"], equation=equation_text(eq)))
    resid_sd = np.nan
    if fits:
        low, low_mode = _lower(*(on_features(e, X) for e in joint_and_brick(fits)))
        resid_sd = float(np.std(y - low, ddof=1))
        rows.append(dict(mode="lower of two", n=len(y), mape_pct=mape(y, low),
                         mode_agreement=float(np.mean(low_mode == mode)), residual_sd_mpa=resid_sd,
                         equation="min(joint, brick)" if len(fits) == 2 else f"the {next(iter(fits))} equation alone"))
    return fits, rows, resid_sd


def joint_and_brick(fits):
    """The joint and the brick equation; with one, it stands for both."""
    eqs = {m: e for m, (e, _) in fits.items()}
    return eqs.get("joint", eqs.get("brick")), eqs.get("brick", eqs.get("joint"))


def equation_terms(terms):
    """The columns of an equations table that carry intervals."""
    return ("intercept",) + tuple(terms) + ("mape_pct",)


def equation_intervals(ns, terms, columns, resamples, seed, progress=None, jobs=1, block=100):
    """95 % bootstrap intervals (statistics.bootstrap_interval, whole samples
    resampled) of the prediction equations of ``prediction_equations``:
    per mode the intercept, the coefficients and the MAPE of the fit
    (each resample refits, penalty chosen by cross-validation included;
    the nested cross-validation is left out), and the lower-of-two MAPE.
    NaN where a resample leaves a mode too few samples to fit.  The
    resamples are fitted in blocks of ``block``, on ``jobs`` processes
    (joblib); each fit is deterministic, so the intervals do not depend on
    ``jobs``.  Returns a frame with the column mode and <term>_lo, <term>_hi."""
    from .statistics import bootstrap_interval
    samples = np.sort(ns["sample"].unique())
    by_sample = [np.flatnonzero(ns["sample"].to_numpy() == s) for s in samples]     # row positions
    arrays = _arrays(ns, terms, columns)
    names = equation_terms(terms)

    def statistic(idx):
        blocks = [idx[k:k + block] for k in range(0, len(idx), block)]
        out, done = [], 0
        for part in map_blocks(_refit_block, blocks, jobs, arrays, by_sample, terms, names):
            out.extend(part)
            done += len(part)
            if progress:
                progress(done, len(idx))
        return np.array(out, float).T
    lo, hi = bootstrap_interval(samples.size, statistic, resamples, seed)
    n = len(names)
    rows = [dict(mode=m, **{f"{t}_{e}": b[k * n + j] for j, t in enumerate(names)
                            for e, b in (("lo", lo), ("hi", hi))}) for k, m in enumerate(("joint", "brick"))]
    return pd.DataFrame(rows + [dict(mode="lower of two", mape_pct_lo=lo[-1], mape_pct_hi=hi[-1])])


def _refit_block(block, arrays, by_sample, terms, names):
    """The statistics of equation_intervals for each resample of a block
    (``arrays``: the runs', ``_arrays``)."""
    out = []
    for idx in block:
        rows = np.concatenate([by_sample[i] for i in idx])
        _, rows, _ = _equations(*(a[rows] for a in arrays), terms, nested=False)
        rows = {r["mode"]: r for r in rows}
        out.append([rows.get(m, {}).get(t, np.nan) for m in ("joint", "brick") for t in names] +
                   [rows.get("lower of two", {}).get("mape_pct", np.nan)])
    return out


def map_blocks(fn, blocks, jobs, *args):
    """fn(block, *args) for each block, in order, as each finishes: in this
    process for one job, else on ``jobs`` joblib (loky) processes.  A
    call gives its values in another process too, at most to round-off:
    numpy's sums can depend in their last bits on where an array lies in
    memory (the refits here: to the bit, tests/test_intervals.py; the
    sensitivity's surrogates: to 1e-12, tests/test_sensitivity.py)."""
    if jobs <= 1:
        return (fn(b, *args) for b in blocks)
    from joblib import Parallel, delayed
    return Parallel(n_jobs=jobs, return_as="generator")(delayed(fn)(b, *args) for b in blocks)
