"""Statistics and prediction equations (docs/study.md, 11-13) on synthetic data with
known answers."""
import numpy as np
import pandas as pd
import pytest

from masonrydem.analysis import statistics as A
from masonrydem.analysis import equations as E
from masonrydem.analysis import validation as V

# a swept level, the terms and the random inputs of the constructed runs below
SV = A.Level("sigma_v_mpa", "sigma_v", "MPa")
TERMS = ("f_tu", "f_tj", "f_tu^2", "f_tj^2", "sigma_v")
INPUTS = ["f_tj_mpa", "f_tu_mpa", "phi_j_deg", "E_b_mpa"]


def _runs():
    """Two variants x two levels; P_max known per group; two failed runs, one
    with a bogus finite P_max, one with none (NaN, as a run without a
    peak)."""
    rows = []
    for variant in ("nonspatial", "spatial"):
        for sv, base in ((0.0, 10.0), (0.5, 15.0)):
            for i, p in enumerate([base - 1, base, base + 1, 2 * base]):
                rows.append(dict(variant=variant, sigma_v_mpa=sv, sample=i, P_max_kN=p,
                                 strength_mpa=p / 7.0, failure_mode="brick" if i == 3 else "joint",
                                 ok=True, f_tj_mpa=0.1 * p, f_tu_mpa=4.0 - 0.01 * p, phi_j_deg=35.0 + i,
                                 E_b_mpa=15000.0))
            for sample, p in ((8, 1e9), (9, np.nan)):
                rows.append(dict(variant=variant, sigma_v_mpa=sv, sample=sample, P_max_kN=p, strength_mpa=p,
                                 failure_mode="joint", ok=False, f_tj_mpa=0.3, f_tu_mpa=3.75, phi_j_deg=35.0,
                                 E_b_mpa=15000.0))
    return pd.DataFrame(rows)


def test_statistics_exclude_failed_runs_and_count_them():
    """Joint runs base-1, base, base+1: mean = base, COV = 1/base; brick run
    2 base alone; brick share 1/4; the failed runs (P = 1e9, P = NaN) are
    excluded and counted."""
    st = A.statistics(_runs(), SV)
    j = st[(st.variant == "nonspatial") & (st.sigma_v_mpa == 0.0) & (st["mode"] == "joint")].iloc[0]
    assert j["count"] == 3 and j.P_max_mean_kN == pytest.approx(10.0)
    assert j.P_max_cov == pytest.approx(1.0 / 10.0)
    assert j.brick_share == pytest.approx(0.25) and j.excluded == 2
    a = st[(st.variant == "spatial") & (st.sigma_v_mpa == 0.5) & (st["mode"] == "all")].iloc[0]
    assert a.P_max_mean_kN == pytest.approx((14 + 15 + 16 + 30) / 4) and a["count"] == 4
    inc = A.increase(st, 0.0, 0.5, SV)
    row = inc[(inc.variant == "nonspatial") & (inc["mode"] == "joint")].iloc[0]
    assert row.increase == pytest.approx(15.0 / 10.0 - 1.0)


def test_running_mean():
    assert A.running_mean([2, 4, 6]).tolist() == [2, 3, 4]


def test_correlations_signs():
    """f_tj rises with P_max (r = +1 in the joint group), f_tu falls (r = -1),
    E_b is constant (no correlation defined: NaN)."""
    c = A.correlations(_runs(), INPUTS, SV)
    j = c[(c.variant == "nonspatial") & (c.sigma_v_mpa == 0.0) & (c["mode"] == "joint")].iloc[0]
    assert j.f_tj_mpa == pytest.approx(1.0) and j.f_tu_mpa == pytest.approx(-1.0)
    assert np.isnan(j.E_b_mpa)


def _study_like(seed, n_samples, noise):
    """n_samples property sets, each at the study's five levels (as the
    runs of one failure mode): strength = 0.4 + 2.0 f_tj + 0.05 f_tu^2 +
    0.9 sigma_v + noise."""
    rng = np.random.default_rng(seed)
    levels = np.array([0.0, 0.075, 0.15, 0.25, 0.5])
    f_tu = np.repeat(rng.lognormal(np.log(3.75), 0.25, n_samples), levels.size)
    f_tj = np.repeat(rng.lognormal(np.log(0.3), 0.4, n_samples), levels.size)
    sv = np.tile(levels, n_samples)
    sample = np.repeat(np.arange(n_samples), levels.size)
    law = 0.4 + 2.0 * f_tj + 0.05 * f_tu ** 2 + 0.9 * sv
    return f_tu, f_tj, sv, law + rng.normal(0, noise, law.size), sample, law


def test_lasso_recovers_known_coefficients():
    """Synthetic strengths (law above, noise sd 0.01 MPa) of 100 samples x
    5 levels: 5-fold CV picks a small penalty and the equation recovers the
    law, every coefficient and the intercept (the irrelevant f_tu and
    f_tj^2 at zero) within 4 of their least-squares standard errors
    sigma sqrt(diag((X^T X)^-1)) on this design (0.0004 to 0.03 MPa per
    unit; measured: within 1 of them), and the MAPE is about the noise
    level (< 1 %) both fitted and out of fold.  (Against least squares
    itself and the Lasso's optimality: tests/test_regression.py.)"""
    f_tu, f_tj, sv, y, sample, _ = _study_like(0, 100, 0.01)
    eq = E.fit_equation(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), y, sample, TERMS)
    X1 = np.column_stack([np.ones(y.size), E.features(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), TERMS)])
    se = 0.01 * np.sqrt(np.diag(np.linalg.inv(X1.T @ X1)))
    got = np.array([eq["intercept"], *(eq["coef"][k] for k in TERMS)])
    law = np.array([0.4, 0.0, 2.0, 0.05, 0.0, 0.9])       # intercept, f_tu, f_tj, f_tu^2, f_tj^2, sigma_v
    assert np.all(np.abs(got - law) <= 4 * se), (got - law) / se
    assert eq["mape"] < 1.0 and eq["cv_mape"] < 1.0
    np.testing.assert_allclose(E.predict(eq, dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv)), eq["fitted"], rtol=1e-10)
    assert "f_tj" in E.equation_text(eq)


def test_out_of_fold_prediction_never_sees_its_own_sample():
    """Out-of-fold predictions come from equations fitted without the
    sample (all its precompression levels): changing every strength of
    sample 3 leaves its own predictions unchanged, and changes the fitted
    equation's.  Noise-free, both MAPEs are small."""
    f_tu, f_tj, sv, y, sample, law = _study_like(1, 12, 0.05)
    a = E.fit_equation(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), y, sample, TERMS)
    y2 = np.where(sample == 3, y + 5.0, y)
    b = E.fit_equation(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), y2, sample, TERMS)
    mine = sample == 3
    np.testing.assert_allclose(b["cv_predicted"][mine], a["cv_predicted"][mine], rtol=1e-12)
    assert np.all(np.abs(b["fitted"][mine] - a["fitted"][mine]) > 1e-3)
    exact = E.fit_equation(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), law, sample, TERMS)
    assert exact["mape"] < 1.0 and exact["cv_mape"] < 1.0


def test_too_few_samples_for_nested_cv():
    """Nested 5-fold CV needs 7 samples (each inner fit 5 of the outer 4/5):
    6 are refused with the reason, 7 fit."""
    f_tu, f_tj, sv, y, sample, _ = _study_like(2, 7, 0.01)
    E.fit_equation(dict(f_tu=f_tu, f_tj=f_tj, sigma_v=sv), y, sample, TERMS)
    six = sample < 6
    with pytest.raises(ValueError, match="at least 7"):
        E.fit_equation(dict(f_tu=f_tu[six], f_tj=f_tj[six], sigma_v=sv[six]), y[six], sample[six], TERMS)


def test_prediction_over_samples():
    """Joint equation 2 f_tj, brick equation 10 - 40 sigma_v: at sigma_v = 0
    the joint one is lower for every sample, so the mean is 2 mean(f_tj) and
    the scatter 2 SD(f_tj); at 0.5 MPa the brick one (-10, the same for all)
    is lower: mean -10, no scatter.  At 0.2 MPa the brick equation gives 2
    and the mean is E[min(2 f_tj, 2)], below min(2 mean(f_tj), 2) (Jensen)."""
    zero = {k: 0.0 for k in TERMS}
    joint = dict(intercept=0.0, coef={**zero, "f_tj": 2.0})
    brick = dict(intercept=10.0, coef={**zero, "sigma_v": -40.0})
    f_tj = np.random.default_rng(2).lognormal(np.log(0.3), 0.4, 100) * 3
    samples = dict(f_tu=np.full(100, 3.75), f_tj=f_tj)
    mean, sd = E.prediction_over_samples(joint, brick, samples, "sigma_v", [0.0, 0.5, 0.2])
    np.testing.assert_allclose(mean[:2], [2.0 * np.mean(f_tj), -10.0], rtol=1e-14)
    np.testing.assert_allclose(sd[:2], [2.0 * np.std(f_tj, ddof=1), 0.0], atol=1e-12)
    np.testing.assert_allclose(mean[2], np.mean(np.minimum(2.0 * f_tj, 2.0)), rtol=1e-14)
    assert mean[2] < min(2.0 * np.mean(f_tj), 2.0)


def test_lower_of_two():
    joint = dict(intercept=1.0, coef={k: 0.0 for k in TERMS})
    brick = dict(intercept=0.0, coef={**{k: 0.0 for k in TERMS}, "sigma_v": 4.0})
    s, mode = E.lower_of_two(joint, brick, dict(f_tu=[3.75] * 3, f_tj=[0.3] * 3, sigma_v=[0.0, 0.25, 0.5]))
    assert s.tolist() == [0.0, 1.0, 1.0] and mode.tolist() == ["brick", "joint", "joint"]


def test_design_rules():
    """Lourenco-Gaetani: 0.36 x 120 / 75 = 0.576 MPa and 3.75 / 2.
    AS3700 with f_mt = 0.3: stepped 2 sqrt(0.3)(1 + f_d/0.3), capped at
    4 sqrt(0.3) (reached at f_d = 0.3); line 0.44 x 3.75 + 0.56 x 0.3."""
    joint, brick = V.lourenco_gaetani(0.36, 3.75, 0.120, 0.075)
    assert joint == pytest.approx(0.576) and brick == 1.875
    stepped, line = V.as3700(0.3, 3.75, [0.0, 0.15, 0.5])
    r = np.sqrt(0.3)
    np.testing.assert_allclose(stepped, [2 * r, 2 * r * 1.5, 4 * r])
    np.testing.assert_allclose(line, 0.44 * 3.75 + 0.56 * 0.3)


def test_one_solver_version():
    """A table of one solver version passes (rows of runs that raised carry
    none); one run from other sources is refused by name."""
    runs = pd.DataFrame(dict(variant=["spatial"] * 4, sigma_v_mpa=[0.15] * 4, sample=[0, 1, 2, 3],
                             solver_version=["0.1.0+aaa", "0.1.0+aaa", None, "0.1.0+aaa"]))
    assert A.check_one_solver(runs, SV) == "0.1.0+aaa"
    runs.loc[1, "solver_version"] = "0.1.0+bbb"
    with pytest.raises(ValueError, match=r"spatial/0.15 MPa/s1 \(0.1.0\+bbb\)"):
        A.check_one_solver(runs, SV)


def test_correlation_band_holds_95_percent_of_independent_correlations():
    """4000 correlations of 100 independent normal pairs: the share outside
    +-correlation_band(100) is 5 % (binomial SD 0.34 %; allowed 4-6 %)."""
    rng = np.random.default_rng(7)
    x, y = rng.standard_normal((2, 4000, 100))
    x, y = x - x.mean(1, keepdims=True), y - y.mean(1, keepdims=True)
    r = (x * y).sum(1) / np.sqrt((x * x).sum(1) * (y * y).sum(1))
    assert 0.04 < np.mean(np.abs(r) > A.correlation_band(100)) < 0.06


def test_input_spread():
    runs = pd.DataFrame(dict(variant=["a"] * 4 + ["b"] * 2, sample=[0, 1, 0, 1, 0, 1], f_tj_mpa=[0.2, 0.4, 0.2, 0.4, 1, 1],
                             f_tu_mpa=3.0, phi_j_deg=35.0, E_b_mpa=15e3))
    cov = A.input_spread(runs, "a", INPUTS)
    np.testing.assert_allclose(cov["f_tj_mpa"], np.std([0.2, 0.4], ddof=1) / 0.3)
    assert cov["f_tu_mpa"] == 0.0 and A.input_spread(runs, "b", INPUTS)["f_tj_mpa"] == 0.0 and A.input_spread(runs, "c", INPUTS) == {}


def test_scatter_level_is_the_nearest_to_the_middle_of_the_range():
    """The scatter plot's level: the study's level nearest the middle of
    its range (0.25 MPa of 0 to 0.5), itself; between levels, the nearer
    one; any swept setting by its column."""
    runs = pd.DataFrame(dict(sigma_v_mpa=[0.5, 0.0, 0.15, 0.25, 0.075]))
    assert A.scatter_level(runs, SV) == 0.25
    t = A.Level("t_mm", "t", "mm")
    assert A.scatter_level(pd.DataFrame(dict(t_mm=[8.0, 10.0, 11.0, 16.0])), t) == 11.0
    assert A.scatter_level(runs, SV, near=0.11) == 0.075 and A.scatter_level(runs, SV, near=0.4) == 0.5


def test_a_run_stopped_before_its_peak_was_certain_is_a_lower_bound():
    """Drive 7.5e-8 m per step, window 0.1 mm: 1333.3 steps.  Stopped by
    the displacement limit 1333 steps after its peak (0.09998 mm): a lower
    bound, not ok, its row kept with why; 1334 steps (0.10005 mm) after, or
    stopped by the load drop, or failed: as they were.  The report names
    the bound among the runs left out."""
    from masonrydem.report.captions import excluded_detail
    runs = pd.DataFrame({"status": ["displacement_limit", "displacement_limit", "load_drop", "diverged",
                                    "displacement_limit"],
                         "ok": [True, True, True, False, True], "steps": [14500, 14500, 14500, 300, 14500],
                         "peak_step": [14500 - 1333, 14500 - 1334, 14499, 200, 14500],
                         "message": ["displacement 0.00101 m reached"] * 2 + ["load", "nan", "displacement"]})
    out = A.lower_bounds(runs, 7.5e-8, 1e-4)
    assert list(out.status) == ["lower_bound", "displacement_limit", "load_drop", "diverged", "lower_bound"]
    assert list(out.ok) == [False, True, True, False, False] and list(runs.ok) == [True, True, True, False, True]
    assert "moved 0.1 mm past the peak, less than the 0.1 mm" in out.message[0] and "0 mm past" in out.message[4]
    assert out.message[1] == runs.message[1]
    assert excluded_detail(out) == " (lower_bound: 2, diverged: 1)" and excluded_detail(runs.iloc[:3]) == ""
    assert A.lower_bounds(runs.iloc[1:4], 7.5e-8, 1e-4).equals(runs.iloc[1:4])
