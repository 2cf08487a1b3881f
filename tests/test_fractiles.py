"""Characteristic strengths (fractiles.py) on distributions whose 5 %
fractile is known in closed form: the estimates converge to it, and the
intervals cover it as often as their confidence says."""
import numpy as np
import pandas as pd
import pytest
from scipy import stats

from masonrydem.analysis import fractiles as F
from masonrydem.analysis.statistics import Level

SIGMA_V = Level("sigma_v_mpa", "sigma_v", "MPa")     # a swept level for the constructed runs

MU, SIGMA = np.log(1.5), 0.3          # a lognormal strength: median 1.5 MPa, COV about 0.31
EXACT = np.exp(MU + stats.norm.ppf(0.05) * SIGMA)


def test_the_ranks_for_a_hundred_runs_are_worked_out_by_hand():
    # B(0; 100, 0.05) = 0.95^100 = 0.0059 <= 0.025 < B(1) = 0.0371: r = 1;
    # B(9) = 0.9718 < 0.975 <= B(10) = 0.9885: s = 11; coverage 0.9885 - 0.0059
    r, s, coverage = F.order_ranks(100)
    assert (r, s) == (1, 11)
    assert coverage == pytest.approx(0.9885 - 0.95 ** 100, abs=1e-4)
    # twenty runs: B(0; 20, 0.05) = 0.358 > 0.025, no order statistic bounds the fractile from below
    assert F.order_ranks(20)[0] is None


def test_both_estimates_converge_to_the_exact_fractile():
    x = np.random.default_rng(1).lognormal(MU, SIGMA, 200_000)
    ln, lo, hi = F.lognormal_fractile(x)
    assert lo < EXACT < hi and ln == pytest.approx(EXACT, rel=2e-3) and hi / lo < 1.01
    em, lo, hi = F.empirical_fractile(x)
    assert lo < EXACT < hi and em == pytest.approx(EXACT, rel=5e-3)


def test_the_lognormal_interval_covers_the_fractile_as_often_as_it_says():
    # 2000 samples of 20: coverage within the binomial 99.9 % range of 0.95 (0.934 to 0.966)
    rng = np.random.default_rng(2)
    hits = [lo < EXACT < hi for lo, hi in (F.lognormal_fractile(rng.lognormal(MU, SIGMA, 20))[1:]
                                           for _ in range(2000))]
    lo, hi = stats.binom.ppf([0.0005, 0.9995], 2000, 0.95) / 2000
    assert lo <= np.mean(hits) <= hi


def test_the_order_statistics_cover_the_fractile_of_any_distribution():
    # a Weibull strength (not lognormal): coverage at least the exact 0.9826, less 3.4 standard errors
    shape, scale = 6.0, 2.0
    exact = scale * (-np.log(0.95)) ** (1 / shape)
    rng = np.random.default_rng(3)
    hits = [lo <= exact <= hi for lo, hi in (F.empirical_fractile(scale * rng.weibull(shape, 100))[1:]
                                             for _ in range(1000))]
    assert np.mean(hits) >= F.order_ranks(100)[2] - 0.015


def test_a_mixture_of_two_modes_is_not_taken_as_lognormal():
    rng = np.random.default_rng(4)
    two = np.r_[rng.lognormal(0.0, 0.08, 60), rng.lognormal(1.0, 0.08, 40)]
    assert F.lognormal_fit(two) < F.NORMALITY_P
    # lognormal samples are rejected at the test's size, 5 %: within the binomial 99.9 % range of 400 tries
    rejected = np.mean([F.lognormal_fit(rng.lognormal(MU, SIGMA, 100)) < F.NORMALITY_P for _ in range(400)])
    lo, hi = stats.binom.ppf([0.0005, 0.9995], 400, F.NORMALITY_P) / 400
    assert lo <= rejected <= hi


def test_the_table_picks_the_supported_estimate_and_adds_the_design_rules():
    rng = np.random.default_rng(5)
    two = np.r_[rng.lognormal(0.0, 0.08, 60), rng.lognormal(1.0, 0.08, 40)]
    runs = pd.DataFrame({"variant": "v", "sigma_v_mpa": np.repeat([0.0, 0.2], 100), "ok": True,
                         "strength_mpa": np.r_[rng.lognormal(MU, SIGMA, 100), two]})
    runs.loc[0, "ok"] = False                                  # a run that failed: not counted
    design = pd.DataFrame({"sigma_v_mpa": [0.0, 0.4], "lg_stepped": [0.5, 0.9], "prediction": [1.0, 2.0]})
    t = F.with_design(F.characteristic_table(runs, SIGMA_V), design, SIGMA_V)
    assert t.n.tolist() == [99, 100] and t.supported.tolist() == ["lognormal", "non-parametric"]
    assert t.characteristic_mpa.tolist() == [t.lognormal_mpa[0], t.empirical_mpa[1]]
    assert t.lg_stepped_mpa.tolist() == pytest.approx([0.5, 0.7]) and "prediction_mpa" not in t
    assert "0.2 MPa" in F.caption_values(t, SIGMA_V)["lines"]
    # a study that sweeps another setting has no design comparison (regression writes a note)
    assert F.with_design(t, pd.DataFrame(dict(note=["no design comparison"])), SIGMA_V) is t
    # two runs: no estimate, and the caption says so instead of printing nan
    few = F.characteristic_table(runs.iloc[:3], SIGMA_V)
    assert few.characteristic_mpa.isna().all() and "nan" not in F.caption_values(few, SIGMA_V)["lines"]


@pytest.mark.parametrize("n, k", [(5, 4.203), (10, 2.911), (20, 2.396), (30, 2.220)])
def test_the_lower_bound_is_the_published_tolerance_limit(n, k):
    """At 90 % two-sided confidence the interval's lower end is the
    one-sided 95 %/95 % lower tolerance limit of the logs, exp(ybar - k s),
    with k the published factor of a normal sample (NIST/SEMATECH e-Handbook,
    7.2.6.3, one-sided factors for p = 0.95, gamma = 0.95; the same as
    ISO 16269-6): 4.203, 2.911, 2.396, 2.220 at n = 5, 10, 20, 30; the
    estimate is exp(ybar - 1.6449 s), s with n - 1."""
    y = np.random.default_rng(n).normal(0.4, 0.2, n)
    ybar, s = y.mean(), np.sqrt(np.sum((y - y.mean()) ** 2) / (n - 1))
    est, lo, _ = F.lognormal_fractile(np.exp(y), confidence=0.90)
    assert lo == pytest.approx(np.exp(ybar - k * s), rel=2e-3 * s)
    assert est == pytest.approx(np.exp(ybar - 1.6448536269514722 * s), rel=1e-12)     # Phi^-1(0.95)


def test_the_runs_a_lower_end_needs_by_its_closed_form():
    """needs.lower_end_runs, (1 - p)^n <= (1 - confidence) / 2 (what
    `masonrydem check` reports before anything runs), is the first n at
    which order_ranks gives the fractile's interval a lower rank: 72 runs
    for the 5 % fractile at 95 %."""
    from masonrydem.analysis.fractiles import order_ranks
    from masonrydem.analysis.needs import lower_end_runs
    assert lower_end_runs() == 72
    for p, conf in ((0.05, 0.95), (0.05, 0.90), (0.10, 0.95), (0.01, 0.95)):
        n = lower_end_runs(p, conf)
        assert order_ranks(n, p, conf)[0] == 1 and order_ranks(n - 1, p, conf)[0] is None, (p, conf)
