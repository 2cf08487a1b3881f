"""The prediction equations (equations.prediction_equations, fit_equation)
against independent computations: least squares with the Lasso's own
optimality bound, hand-scored predictors on constructed runs."""
import numpy as np
import pandas as pd
import pytest
from sklearn.linear_model import Lasso

from masonrydem.analysis import equations as E

# the terms and the inputs' columns of the constructed runs below
TERMS = ("f_tu", "f_tj", "f_tu^2", "f_tj^2", "sigma_v")
COLUMNS = {"f_tj": "f_tj_mpa", "f_tu": "f_tu_mpa", "sigma_v": "sigma_v_mpa"}

LEVELS = np.array([0.0, 0.075, 0.15, 0.25, 0.5])


def _samples(seed, n):
    """n property sets at the five levels: (f_tu, f_tj, sigma_v, sample)."""
    rng = np.random.default_rng(seed)
    f_tu = np.repeat(rng.lognormal(np.log(3.75), 0.25, n), LEVELS.size)
    f_tj = np.repeat(rng.lognormal(np.log(0.3), 0.4, n), LEVELS.size)
    return f_tu, f_tj, np.tile(LEVELS, n), np.repeat(np.arange(n), LEVELS.size)


def _standardised(X):
    mean, scale = X.mean(axis=0), X.std(axis=0)
    return (X - mean) / scale, mean, scale


def test_lasso_against_least_squares_within_its_optimality_bound():
    """On standardised features Z (n rows) the Lasso minimises
    |y - b0 - Z b|^2 / 2n + alpha |b|_1.  Its optimality conditions: the
    gradient g = Z^T (y - b0 - Z b) / n equals alpha sign(b_j) where b_j is
    not zero and lies within +-alpha where it is; checked on the fitted
    equation brought back to standardised units, to 1e-6 alpha (the
    default solver tolerance missed them by 6 % of alpha on f_tu here).
    Least squares has g = 0, so (Z^T Z / n)(b_ls - b) = alpha s, |s_j| <= 1,
    and |b_ls - b| <= alpha sqrt(p) / lambda_min(Z^T Z / n): the equation
    lies within that bound of the least-squares solution (numpy lstsq, an
    independent method), and a plain Lasso at the chosen alpha (the
    features standardised by hand) gives the same coefficients."""
    f_tu, f_tj, sv, sample = _samples(3, 60)
    y = 0.4 + 2.0 * f_tj + 0.05 * f_tu ** 2 + 0.9 * sv + np.random.default_rng(4).normal(0, 0.01, sv.size)
    eq = E.fit_equation(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), y, sample, TERMS)
    alpha = eq["alpha"]
    Z, mean, scale = _standardised(E.features(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), TERMS))
    b = np.array([eq["coef"][k] for k in TERMS]) * scale
    b0 = eq["intercept"] + np.sum(b / scale * mean)
    g = Z.T @ (y - b0 - Z @ b) / len(y)
    active = b != 0
    np.testing.assert_allclose(g[active], alpha * np.sign(b[active]), rtol=0, atol=1e-6 * alpha)
    assert np.all(np.abs(g[~active]) <= alpha * (1 + 1e-6))
    ls = np.linalg.lstsq(np.column_stack([np.ones(len(y)), Z]), y, rcond=None)[0]
    lam = np.linalg.eigvalsh(Z.T @ Z / len(y)).min()
    assert np.linalg.norm(ls[1:] - b) <= alpha * np.sqrt(Z.shape[1]) / lam
    plain = Lasso(alpha=alpha, max_iter=1_000_000, tol=1e-12).fit(Z, y)
    np.testing.assert_allclose(b, plain.coef_, rtol=0, atol=1e-6 * np.abs(plain.coef_).max())
    assert b0 == pytest.approx(plain.intercept_, abs=1e-6)



@pytest.mark.parametrize("law", ["joint", "brick", "noise"])
def test_the_penalty_and_coefficients_are_lasso_cvs(law):
    """The exact path (equations._lasso) makes scikit-learn LassoCV's
    choice, an independent method (coordinate descent, to a duality gap of
    1e-12, on the same folds of whole samples): the same penalty, and
    coefficients within 1e-7 of the largest; on pure noise, with the same
    penalty, no term at all or the same ones."""
    from sklearn.linear_model import LassoCV
    from sklearn.model_selection import GroupKFold
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler
    f_tu, f_tj, sv, sample = _samples(7, 40)
    noise = np.random.default_rng(8).normal(0, 0.05, sv.size)
    y = {"joint": 0.2 + 3.0 * f_tj + 1.1 * sv + noise, "brick": 0.3 + 0.4 * f_tu - 0.01 * f_tu ** 2 + noise,
         "noise": 1.0 + noise}[law]
    X = E.features(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), TERMS)
    cv = list(GroupKFold(5).split(X, y, sample))
    ref = make_pipeline(StandardScaler(), LassoCV(cv=cv, max_iter=10_000_000, tol=1e-12)).fit(X, y)[1]
    fit = E._lasso(X, y, sample)
    assert fit.alpha == pytest.approx(ref.alpha_, rel=1e-12)
    np.testing.assert_allclose(fit.coef, ref.coef_, rtol=0, atol=1e-7 * max(np.abs(ref.coef_).max(), 1e-12))
    assert fit.intercept == pytest.approx(ref.intercept_, abs=1e-7)
    assert set(np.flatnonzero(fit.coef)) == set(np.flatnonzero(ref.coef_))

def _runs(joint_law, brick_law, n_joint, n_brick, seed=5):
    """Non-spatial ok runs: samples 0..n_joint-1 fail in the joints at
    every level, the next n_brick in the bricks, each by its exact law."""
    f_tu, f_tj, sv, sample = _samples(seed, n_joint + n_brick)
    mode = np.where(sample < n_joint, "joint", "brick")
    strength = np.where(mode == "joint", joint_law(f_tu, f_tj, sv), brick_law(f_tu, f_tj, sv))
    return pd.DataFrame(dict(variant="nonspatial", ok=True, sample=sample, sigma_v_mpa=sv, f_tu_mpa=f_tu,
                             f_tj_mpa=f_tj, failure_mode=mode, strength_mpa=strength))


def JOINT(f_tu, f_tj, sv):
    return 0.3 + 3.0 * f_tj + 2.0 * sv


def BRICK(f_tu, f_tj, sv):
    return 0.5 + 0.5 * f_tu + 0.2 * f_tj


def test_each_mode_gets_its_own_equation():
    """Joint-mode runs follow one exact law, brick-mode runs another: each
    mode's equation recovers its own law (fitted MAPE below 0.5 %), not a
    mixture of the two (which would miss both by several per cent)."""
    ns = _runs(JOINT, BRICK, 12, 12)
    fits, rows, _ = E.prediction_equations(ns, TERMS, COLUMNS)
    assert set(fits) == {"joint", "brick"}
    for mode, law in (("joint", JOINT), ("brick", BRICK)):
        g = ns[ns.failure_mode == mode]
        pred = E.predict(fits[mode][0], dict(f_tu=g.f_tu_mpa, f_tj=g.f_tj_mpa, sigma_v=g.sigma_v_mpa))
        assert E.mape(law(g.f_tu_mpa, g.f_tj_mpa, g.sigma_v_mpa), pred) < 0.5, mode
        np.testing.assert_array_equal(fits[mode][1], g.strength_mpa.to_numpy())
    table = pd.DataFrame(rows).set_index("mode")
    assert table.loc["joint", "n"] == table.loc["brick", "n"] == 60


def test_the_lower_of_two_row_scored_by_hand():
    """The 'lower of two' row: from the two returned equations, the
    predicted strength is the lower one and its mode the lower one's; its
    MAPE, mode agreement (the share of runs whose predicted mode is their
    simulated one) and residual SD (of simulated minus predicted, ddof 1)
    are those computed here by hand over every run."""
    ns = _runs(JOINT, BRICK, 10, 9)
    fits, rows, resid_sd = E.prediction_equations(ns, TERMS, COLUMNS)
    j = E.predict(fits["joint"][0], dict(f_tu=ns.f_tu_mpa, f_tj=ns.f_tj_mpa, sigma_v=ns.sigma_v_mpa))
    b = E.predict(fits["brick"][0], dict(f_tu=ns.f_tu_mpa, f_tj=ns.f_tj_mpa, sigma_v=ns.sigma_v_mpa))
    low = np.where(j <= b, j, b)
    mode = np.where(j <= b, "joint", "brick")
    y = ns.strength_mpa.to_numpy()
    row = pd.DataFrame(rows).set_index("mode").loc["lower of two"]
    assert row.n == len(ns) and row.equation == "min(joint, brick)"
    assert row.mape_pct == pytest.approx(100.0 * np.mean(np.abs(low - y) / y), rel=1e-12)
    assert row.mode_agreement == pytest.approx(np.mean(mode == ns.failure_mode.to_numpy()), rel=1e-12)
    assert resid_sd == row.residual_sd_mpa == pytest.approx(np.std(y - low, ddof=1), rel=1e-12)


def test_a_mode_with_too_few_samples_is_not_fitted_and_the_other_stands_for_both():
    """Brick failures in 6 samples (fewer than MIN_SAMPLES = 7): no brick
    equation, a row saying why, and the joint equation alone scores every
    run, the brick runs included."""
    ns = _runs(JOINT, BRICK, 10, 6)
    fits, rows, resid_sd = E.prediction_equations(ns, TERMS, COLUMNS)
    table = pd.DataFrame(rows).set_index("mode")
    assert set(fits) == {"joint"}
    assert table.loc["brick", "n"] == 30 and "too few runs to fit (6 samples" in table.loc["brick", "equation"]
    assert table.loc["lower of two", "equation"] == "the joint equation alone"
    pred = E.predict(fits["joint"][0], dict(f_tu=ns.f_tu_mpa, f_tj=ns.f_tj_mpa, sigma_v=ns.sigma_v_mpa))
    assert resid_sd == pytest.approx(np.std(ns.strength_mpa - pred, ddof=1), rel=1e-12)
    assert table.loc["lower of two", "mode_agreement"] == pytest.approx(10 / 16)


def test_no_mode_with_enough_samples_fits_nothing():
    fits, rows, resid_sd = E.prediction_equations(_runs(JOINT, BRICK, 6, 6), TERMS, COLUMNS)
    assert fits == {} and np.isnan(resid_sd) and [r["mode"] for r in rows] == ["joint", "brick"]


def test_the_folds_hold_whole_samples(monkeypatch):
    """prediction_equations passes each run's sample as its group (a fold
    holds a sample at every level), the mode's runs only."""
    seen = {}
    real = E.fit_features

    def spy(X, strength, groups, *args, **kw):
        seen[len(seen)] = (np.asarray(groups).copy(), np.asarray(X[:, TERMS.index("f_tu")]).copy())
        return real(X, strength, groups, *args, **kw)

    monkeypatch.setattr(E, "fit_features", spy)
    ns = _runs(JOINT, BRICK, 8, 8).sample(frac=1.0, random_state=0)        # rows shuffled
    E.prediction_equations(ns, TERMS, COLUMNS)
    for k, mode in enumerate(("joint", "brick")):
        g = ns[ns.failure_mode == mode]
        np.testing.assert_array_equal(seen[k][0], g["sample"].to_numpy())
        np.testing.assert_array_equal(seen[k][1], g.f_tu_mpa.to_numpy())


def _lasso_cv_predict(X_train, y_train, g_train, X_test):
    """scikit-learn LassoCV (coordinate descent to a duality gap of 1e-12)
    on standardised features, its penalty chosen on 5 folds of whole
    samples: an independent implementation of one fit of the equations."""
    from sklearn.linear_model import LassoCV
    from sklearn.model_selection import GroupKFold
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler
    cv = list(GroupKFold(5).split(X_train, y_train, g_train))
    model = make_pipeline(StandardScaler(), LassoCV(cv=cv, max_iter=10_000_000, tol=1e-12))
    return model.fit(X_train, y_train).predict(X_test)


def test_the_out_of_fold_error_is_that_of_an_independent_refit_per_fold():
    """The equations' out-of-fold MAPE, the error to expect on a wallette
    the fit has not seen: each outer fold of whole samples refitted by
    LassoCV (its own penalty chosen on the fold's four fifths) predicts the
    held-out fifth; their MAPE is the one reported, to 1e-6 (coordinate
    descent's tolerance on the coefficients)."""
    from sklearn.model_selection import GroupKFold
    f_tu, f_tj, sv, sample = _samples(9, 30)
    rng = np.random.default_rng(10)
    y = 0.3 + 3.0 * f_tj + 0.02 * f_tu ** 2 + 1.5 * sv + rng.normal(0, 0.05, sv.size)
    inputs = dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv)
    eq = E.fit_equation(inputs, y, sample, TERMS)
    X = E.features(inputs, TERMS)
    oof = np.full_like(y, np.nan)
    for train, test in GroupKFold(5).split(X, y, sample):
        oof[test] = _lasso_cv_predict(X[train], y[train], sample[train], X[test])
    independent = 100.0 * np.mean(np.abs((oof - y) / y))
    assert eq["cv_mape"] == pytest.approx(independent, rel=1e-6)
    np.testing.assert_allclose(eq["cv_predicted"], oof, rtol=1e-6)
    assert eq["cv_mape"] > eq["mape"]           # unseen wallettes are predicted worse than the fitted ones


def _parsed(text):
    """An equation as equation_text prints it, 'sigma = 0.3 + 3 f_tj - 0.01
    f_tu^2 ... (MPa)', read back: (intercept, term -> coefficient)."""
    import re
    body = text.removeprefix("sigma = ").removesuffix("(MPa)").strip()
    head, *rest = re.split(r" (?=[+-] )", body)
    coef = {}
    for part in rest:
        sign, value, term = part.split(" ", 2)
        coef[term] = float(value) * (1 if sign == "+" else -1)
    return float(head), coef


def test_the_printed_equation_gives_the_equations_predictions_to_its_digits():
    """The equation as the table prints it (four significant digits each),
    parsed back, predicts every run within the rounding it implies: each
    coefficient within half a unit of its fourth digit."""
    f_tu, f_tj, sv, sample = _samples(11, 20)
    y = 0.35 + 2.8 * f_tj - 0.013 * f_tu ** 2 + 1.9 * sv + np.random.default_rng(12).normal(0, 0.02, sv.size)
    inputs = dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv)
    eq = E.fit_equation(inputs, y, sample, TERMS)
    intercept, coef = _parsed(E.equation_text(eq))
    assert set(coef) == {k for k, c in eq["coef"].items() if c != 0}
    printed = dict(intercept=intercept, coef={k: coef.get(k, 0.0) for k in TERMS})
    X = E.features(inputs, TERMS)
    bound = 0.5 * 10 ** (np.floor(np.log10(np.abs(eq["intercept"]))) - 3) + sum(
        0.5 * 10 ** (np.floor(np.log10(abs(c))) - 3) * np.abs(X[:, k]) for k, c in enumerate(eq["coef"].values()) if c)
    assert np.all(np.abs(E.predict(printed, inputs) - E.predict(eq, inputs)) <= bound * (1 + 1e-9))
    for k, c in eq["coef"].items():
        if c:
            assert coef[k] == pytest.approx(c, rel=5.01e-4), k


def test_the_brick_and_lower_of_two_intervals_hold_their_truths():
    """Each run fails in the mode of the lower of two known laws, with
    noise (SD 0.02 MPa): the brick equation's intervals hold its true
    intercept and f_tu coefficient, and the lower-of-two MAPE interval holds
    the lower-of-two MAPE on these runs, which is about the noise's share
    of a strength (about 1 %); every mode's MAPE interval holds its
    estimate."""
    rng = np.random.default_rng(13)
    f_tu, f_tj, sv, sample = _samples(14, 50)
    j, b = JOINT(f_tu, f_tj, sv), 0.2 + 0.35 * f_tu + 0.2 * f_tj
    ns = pd.DataFrame(dict(variant="nonspatial", ok=True, sample=sample, sigma_v_mpa=sv, f_tu_mpa=f_tu, f_tj_mpa=f_tj,
                           failure_mode=np.where(j <= b, "joint", "brick"),
                           strength_mpa=np.minimum(j, b) + rng.normal(0, 0.02, sv.size)))
    assert 0.2 < (ns.failure_mode == "brick").mean() < 0.8
    ci = E.equation_intervals(ns, TERMS, COLUMNS, resamples=200, seed=0).set_index("mode")
    _, rows, _ = E.prediction_equations(ns, TERMS, COLUMNS)
    rows = {r["mode"]: r for r in rows}
    for term, true in (("intercept", 0.2), ("f_tu", 0.35), ("f_tj", 0.2)):
        assert ci.loc["brick", f"{term}_lo"] <= true <= ci.loc["brick", f"{term}_hi"], term
    for mode in ("joint", "brick", "lower of two"):
        assert ci.loc[mode, "mape_pct_lo"] <= rows[mode]["mape_pct"] <= ci.loc[mode, "mape_pct_hi"], mode
    assert 0.2 < ci.loc["lower of two", "mape_pct_lo"] and ci.loc["lower of two", "mape_pct_hi"] < 2.5
    # the residual scatter the predictor leaves: the standard deviation (n - 1) of simulated - predicted
    fits, _, resid_sd = E.prediction_equations(ns, TERMS, COLUMNS)
    low, _ = E.lower_of_two(fits["joint"][0], fits["brick"][0], dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv))
    r = ns.strength_mpa.to_numpy() - low
    assert resid_sd == pytest.approx(np.sqrt(np.sum((r - r.mean()) ** 2) / (r.size - 1)), rel=1e-12)
    assert rows["lower of two"]["residual_sd_mpa"] == resid_sd


def test_the_lower_of_two_mape_interval_is_that_of_both_modes_runs():
    """Each run fails in the mode of the lower of two known laws, its
    strength that law's times 1 + e, e normal with SD 0.5 % in the joint
    mode and 5 % in the brick mode: the lower of two predicts each run
    with its mode's equation (the two agree where they cross), so its MAPE
    is the mean of |e| over all runs, sqrt(2 / pi) (0.5 % p_joint + 5 %
    p_brick) with p the modes' shares of the runs (E|e| = sigma sqrt(2 /
    pi)), about 2.2 %; the fits take a little of it (their few terms among
    200 runs).  Its interval holds that value, and so is neither the joint
    fit's MAPE interval (about 0.4 %) nor the brick's (about 4 %)."""
    rng = np.random.default_rng(15)
    f_tu, f_tj, sv, sample = _samples(16, 40)
    j, b = JOINT(f_tu, f_tj, sv), 0.2 + 0.35 * f_tu + 0.2 * f_tj
    mode = np.where(j <= b, "joint", "brick")
    sd = np.where(mode == "joint", 0.005, 0.05)
    ns = pd.DataFrame(dict(variant="nonspatial", ok=True, sample=sample, sigma_v_mpa=sv, f_tu_mpa=f_tu, f_tj_mpa=f_tj,
                           failure_mode=mode, strength_mpa=np.minimum(j, b) * (1 + sd * rng.standard_normal(sv.size))))
    assert 0.3 < (mode == "brick").mean() < 0.7
    expected = 100 * np.sqrt(2 / np.pi) * sd.mean()
    ci = E.equation_intervals(ns, TERMS, COLUMNS, resamples=200, seed=0).set_index("mode")
    assert ci.loc["lower of two", "mape_pct_lo"] <= expected <= ci.loc["lower of two", "mape_pct_hi"]
    for m in ("joint", "brick"):
        assert not ci.loc[m, "mape_pct_lo"] <= expected <= ci.loc[m, "mape_pct_hi"], m
