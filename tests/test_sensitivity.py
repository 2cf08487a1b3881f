"""Sobol indices (sensitivity.py) on functions whose indices are known in
closed form: an additive function of independent inputs, and a sum of two
correlated normals through the Gaussian copula."""
import numpy as np
import pandas as pd
import pytest

from masonrydem.analysis import sensitivity as S
from masonrydem.analysis.statistics import Level

SIGMA_V = Level("sigma_v_mpa", "sigma_v", "MPa")     # a swept level for the constructed runs
from masonrydem.study.sampling import Variable


UNIFORMS = [Variable(f"x{k}", "uniform", bounds=(0.0, 1.0)) for k in range(1, 5)]
SCALE = {f"x{k}": 1.0 for k in range(1, 5)}


def runs_of(to_inputs, f, n, noise, seed):
    rng = np.random.default_rng(seed)
    x = to_inputs(rng.random((n, 4)))
    return x, f(x) + noise * rng.standard_normal(n)


def test_an_additive_function_of_independent_inputs():
    """y = 3 x1 + 2 x2 + x3 (+ 0 x4), x_k uniform: S1 = ST = a_k^2 / sum a^2
    = (9, 4, 1, 0) / 14; from 200 noisy runs, the indices within 0.02 and
    inside their intervals."""
    to_inputs = S.input_map(UNIFORMS, {}, SCALE)
    a = np.array([3.0, 2.0, 1.0, 0.0])
    x, y = runs_of(to_inputs, lambda x: x @ a, 200, 0.05, 1)
    res = S.group_indices(x, y, S.sobol_points(4), to_inputs)
    exact = a ** 2 / np.sum(a ** 2)
    assert res["surrogate"] in ("linear", "quadratic") and res["cv_r2"] > 0.99
    for s in ("S1", "ST"):
        np.testing.assert_allclose(res[s], exact, atol=0.02)
        assert np.all(res[f"{s}_lo"] - 1e-3 <= exact) and np.all(exact <= res[f"{s}_hi"] + 1e-3), s


def test_the_sobol_points_alone_give_the_indices_to_a_hundredth():
    """Without a surrogate: the estimators on an exactly known function at
    N_BASE points (the error the docstring states)."""
    to_inputs = S.input_map(UNIFORMS, {}, SCALE)
    a = np.array([3.0, 2.0, 1.0, 0.0])
    s1, st = S.indices(to_inputs(S.sobol_points(4)) @ a, 4)
    np.testing.assert_allclose(s1, a ** 2 / 14, atol=0.01)
    np.testing.assert_allclose(st, a ** 2 / 14, atol=0.01)


def test_a_correlated_pair_splits_into_full_and_independent_parts():
    """x2, x4 standard normal with correlation rho = 0.5, y = x2 + x4: with
    x4 = rho w2 + sqrt(1 - rho^2) w4, y = (1 + rho) w2 + sqrt(1 - rho^2) w4,
    so x2 (first in order) has index (1 + rho) / 2 = 0.75 and x4 its
    independent part (1 - rho) / 2 = 0.25.  The map reproduces the
    correlation and the marginals."""
    normals = [Variable(f"x{k}", "normal", mean=0.0, sd=1.0) for k in range(1, 5)]
    to_inputs = S.input_map(normals, {("x2", "x4"): 0.5}, SCALE)
    x = to_inputs(np.random.default_rng(2).random((40_000, 4)))
    c = np.corrcoef(x, rowvar=False)
    assert c[1, 3] == pytest.approx(0.5, abs=0.02) and abs(c[0, 1]) < 0.02
    np.testing.assert_allclose(x.std(axis=0), 1.0, atol=0.02)
    xs, y = runs_of(to_inputs, lambda x: x[:, 1] + x[:, 3], 300, 0.05, 3)
    res = S.group_indices(xs, y, S.sobol_points(4), to_inputs)
    np.testing.assert_allclose(res["ST"], [0, 0.75, 0, 0.25], atol=0.03)
    np.testing.assert_allclose(res["S1"], [0, 0.75, 0, 0.25], atol=0.03)


def test_no_indices_where_the_inputs_do_not_explain_the_strength():
    """Strengths that are noise, and a mode with too few runs: rows kept,
    without indices."""
    rng = np.random.default_rng(4)
    n = 60
    runs = pd.DataFrame({"variant": "v", "sigma_v_mpa": 0.0, "ok": True, "strength_mpa": rng.random(n),
                         "failure_mode": ["joint"] * (n - 5) + ["brick"] * 5,
                         **{f"x{k}": rng.random(n) for k in range(1, 5)}})
    t = S.sensitivity_table(runs, SIGMA_V, [f"x{k}" for k in range(1, 5)], S.input_map(UNIFORMS, {}, SCALE),
                            bootstrap=5)
    assert t.groupby("mode").size().to_dict() == {"all": 4, "joint": 4, "brick": 1}
    assert (t.cv_r2.dropna() < S.MIN_R2).all() and t.S1.isna().all()
    t = S.with_pearson(t, pd.DataFrame({"variant": ["v"] * 3, "sigma_v_mpa": 0.0, "mode": ["all", "joint", "brick"],
                                        **{f"x{k}": 0.1 for k in range(1, 5)}}), SIGMA_V)
    text = S.caption_values(t, SIGMA_V, UNIFORMS, {})["lines"]
    assert "no indices" in text and "nan" not in text


def test_the_figure_draws_an_estimate_outside_its_interval(tmp_path):
    """A percentile interval need not hold its estimate (a total index near
    0 whose resamples all lie above it): the figure still draws."""
    t = pd.DataFrame(dict(variant="v", sigma_v_mpa=[0.0, 0.5], mode="all", runs=100, input="x1", surrogate="linear",
                          cv_r2=0.9, S1=[0.001, 0.5], S1_lo=[0.002, 0.4], S1_hi=[0.01, 0.6], ST=[0.001, 0.5],
                          ST_lo=[0.002, 0.4], ST_hi=[0.01, 0.6], pearson_sq=[0.0, 0.4]))
    S.figure(t, tmp_path / "s.png", SIGMA_V)
    assert (tmp_path / "s.png").stat().st_size > 0
