"""Sobol indices (analysis/sensitivity.py) on functions whose indices are
known in closed form: an additive function of independent inputs, a
function with an interaction (total and first-order indices differ), a
sum of two correlated normals through the Gaussian copula; through the
table, in units that are not the variables' SI ones, mapped to the inputs
by name; and through the workflow's rule."""
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


def test_an_interaction_separates_total_from_first_order_indices():
    """y = x1 + x2 + 3 x1 x2 (+ 0 x3, 0 x4), x1, x2 uniform on (-1, 1):
    Var(y) = 1/3 + 1/3 + 9 (1/3)^2 = 5/3; E[y | x1] = x1, so S1 = (1/3) /
    (5/3) = 0.2 for each; the interaction's variance 1 belongs to both
    totals: ST = (1/3 + 1) / (5/3) = 0.8.  A linear surrogate cannot show
    it; the quadratic one (its cross term) is chosen, and a total index
    taken as the first-order one would miss by 0.6."""
    sym = [Variable(f"x{k}", "uniform", bounds=(-1.0, 1.0)) for k in range(1, 5)]
    to_inputs = S.input_map(sym, {}, SCALE)
    x, y = runs_of(to_inputs, lambda x: x[:, 0] + x[:, 1] + 3.0 * x[:, 0] * x[:, 1], 300, 0.02, 5)
    res = S.group_indices(x, y, S.sobol_points(4), to_inputs, bootstrap=20)
    assert res["surrogate"] == "quadratic" and res["cv_r2"] > 0.99
    np.testing.assert_allclose(res["S1"], [0.2, 0.2, 0.0, 0.0], atol=0.02)
    np.testing.assert_allclose(res["ST"], [0.8, 0.8, 0.0, 0.0], atol=0.02)


def _table_runs(variables, f, n, seed, scale):
    """Runs of one variant and level whose strength is f of the inputs in
    the runs table's units (each SI value times scale[name])."""
    rng = np.random.default_rng(seed)
    u = rng.random((n, len(variables)))
    cols = {v.name: scale[v.name] * v.frozen().ppf(u[:, k]) for k, v in enumerate(variables)}
    return pd.DataFrame({"variant": "v", "sigma_v_mpa": 0.0, "ok": True, "failure_mode": "joint",
                         **{f"{k}_mpa": x for k, x in cols.items()}, "strength_mpa": f(cols)})


def test_the_table_names_each_index_by_its_input_in_the_runs_units():
    """Two stresses given in Pa and shown in MPa (a scale of 1e-6, not 1),
    the runs table's columns in the order b, a where the variables run a,
    b: strength = 2 a + 0.5 b + a b (MPa).  With a ~ U(1, 3) and b ~ U(0, 2)
    MPa (variances 1/3): E[y | a] = (2 + E b) a + ..., so V_a = 3^2 / 3;
    E[y | b] = (0.5 + E a) b + ..., V_b = 2.5^2 / 3; the interaction
    V_ab = Var a Var b = 1/9; S1 = V / (V_a + V_b + V_ab), ST adds V_ab.
    The table's row of a_mpa carries a's indices, b_mpa b's."""
    var_a, var_b = 1.0 / 3.0, 1.0 / 3.0                   # U over a width of 2
    v_a, v_b, v_ab = (2.0 + 1.0) ** 2 * var_a, (0.5 + 2.0) ** 2 * var_b, var_a * var_b
    total = v_a + v_b + v_ab
    exact = {"a_mpa": (v_a / total, (v_a + v_ab) / total), "b_mpa": (v_b / total, (v_b + v_ab) / total)}
    variables = [Variable("a", "uniform", bounds=(1e6, 3e6)), Variable("b", "uniform", bounds=(0.0, 2e6))]
    scale = {"a": 1e-6, "b": 1e-6}
    runs = _table_runs(variables, lambda c: 2 * c["a"] + 0.5 * c["b"] + c["a"] * c["b"], 200, 6, scale)
    t = S.sensitivity_table(runs, SIGMA_V, ["a_mpa", "b_mpa"], S.input_map(variables, {}, scale), bootstrap=10)
    t = t[t["mode"] == "all"].set_index("input")
    for col, (s1, st) in exact.items():
        assert t.loc[col, "S1"] == pytest.approx(s1, abs=0.02) and t.loc[col, "ST"] == pytest.approx(st, abs=0.02), col
    # a map that leaves the runs' values in SI (scale 1) evaluates the
    # surrogate a million times off its range: the indices say nothing
    wrong = S.sensitivity_table(runs, SIGMA_V, ["a_mpa", "b_mpa"], S.input_map(variables, {}, {"a": 1, "b": 1}),
                                bootstrap=2)
    assert not np.allclose(wrong[wrong["mode"] == "all"].S1.to_numpy(), t.S1.to_numpy(), atol=0.05)


def test_a_correlated_pair_through_the_table():
    """The correlated pair of the test above, in the table: the input first
    in the study's order carries the full index 0.75."""
    normals = [Variable("p", "normal", mean=5e6, sd=1e6), Variable("q", "normal", mean=5e6, sd=1e6)]
    scale = {"p": 1e-6, "q": 1e-6}
    to_inputs = S.input_map(normals, {("p", "q"): 0.5}, scale)
    x = to_inputs(np.random.default_rng(7).random((300, 2)))
    runs = pd.DataFrame({"variant": "v", "sigma_v_mpa": 0.0, "ok": True, "failure_mode": "brick", "p_mpa": x[:, 0],
                         "q_mpa": x[:, 1], "strength_mpa": x[:, 0] + x[:, 1]})
    t = S.sensitivity_table(runs, SIGMA_V, ["p_mpa", "q_mpa"], to_inputs, bootstrap=5)
    t = t[t["mode"] == "brick"].set_index("input")
    assert t.loc["p_mpa", "ST"] == pytest.approx(0.75, abs=0.03) and t.loc["q_mpa", "ST"] == pytest.approx(0.25,
                                                                                                          abs=0.03)


def test_the_table_on_two_processes_is_the_table_on_one():
    """The groups (here two levels, each with its 'all' and its modes, one
    of them too small for indices) computed on two processes give the same
    table, in the same order, every value to round-off (1e-12 relative;
    the table is written to 4 digits): each group draws from its own seed,
    whichever process fits it."""
    variables = [Variable("a", "uniform", bounds=(1e6, 3e6)), Variable("b", "uniform", bounds=(0.0, 2e6))]
    scale = {"a": 1e-6, "b": 1e-6}
    parts = []
    for k, level in enumerate((0.0, 0.5)):
        r = _table_runs(variables, lambda c: 2 * c["a"] + c["a"] * c["b"], 60, k, scale).assign(sigma_v_mpa=level)
        r.loc[r.index[:5], "failure_mode"] = "brick"          # 5 brick runs: below MIN_RUNS
        parts.append(r)
    runs = pd.concat(parts, ignore_index=True)
    args = (runs, SIGMA_V, ["a_mpa", "b_mpa"], S.input_map(variables, {}, scale))
    one, two = S.sensitivity_table(*args, bootstrap=3, jobs=1), S.sensitivity_table(*args, bootstrap=3, jobs=2)
    assert one.S1.notna().sum() >= 4
    pd.testing.assert_frame_equal(one, two, check_exact=False, rtol=1e-12, atol=0.0)
