"""The lab's uncertainty carried to the wallette by re-weighting the runs
(analysis/design.py), against closed forms and brute force: a tiny
synthetic study y = x1 x2 whose 5 % fractile is lognormal in closed form,
rerun from scratch at every resampled lab fit; the lab's bootstrap against
its closed forms; and the whole design table against a second
implementation of the chain with the test's own parametric bootstrap
(numpy alone), within the two bootstraps' Monte Carlo error."""
import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from masonrydem.analysis import design as D
from masonrydem.analysis import fractiles

Z = stats.norm.ppf(0.05)


def test_weighted_quantile_is_the_quantile_of_the_values_repeated():
    g = np.random.default_rng(17)
    for _ in range(30):
        v, w = g.normal(size=37), g.integers(1, 6, 37)
        for p in (0.05, 0.5, 0.95):
            assert D.weighted_quantile(v, w, p) == np.quantile(np.repeat(v, w), p, method="inverted_cdf")
    assert D.ess(np.ones(40)) == pytest.approx(40) and D.ess(np.r_[1.0, np.zeros(9)]) == pytest.approx(1)


def test_weighted_lognormal_fractile_at_equal_weights_is_the_studys():
    y = np.random.default_rng(18).lognormal(0.3, 0.2, 25)
    assert D.weighted_fractile(y, np.full(25, 3.0), 0.05, "lognormal") == pytest.approx(fractiles.lognormal_fractile(y)[0])


def test_density_has_the_studys_mean_and_cov():
    for dist in ("lognormal", "normal"):
        d = D.density(dist, 0.3, 0.2)
        assert d.mean() == pytest.approx(0.3) and d.std() / d.mean() == pytest.approx(0.2)


def _exact(m1, c1, mu2, s2):
    """The 5 % fractile of y = x1 x2, x1 lognormal of mean m1 and cov c1,
    ln x2 normal (mu2, s2): ln y is normal."""
    s1 = np.sqrt(np.log1p(np.square(c1)))
    return np.exp(np.log(m1) - s1 ** 2 / 2 + mu2 + Z * np.sqrt(s1 ** 2 + s2 ** 2))


def _fit(lab):
    """The lab's mean and cov, the sum of squares over n - 1 written out."""
    return lab.mean(), math.sqrt(np.sum((lab - lab.mean()) ** 2) / (lab.size - 1)) / lab.mean()


def _lognormal(m, c):
    """The lognormal of mean m and cov c: sigma^2 = ln(1 + c^2), median m / sqrt(1 + c^2)."""
    return stats.lognorm(math.sqrt(math.log1p(c * c)), scale=m / math.sqrt(1 + c * c))


def _own_bootstrap(lab, dist, B, g):
    """The lab's parametric bootstrap written again from numpy: B labs of n
    values drawn from the fit (lognormal of the lab's mean m and cov c,
    sigma^2 = ln(1 + c^2), mu = ln m - sigma^2 / 2; or normal), each one's
    mean and cov (sum of squares over n - 1)."""
    n, (m, c) = lab.size, _fit(lab)
    s = math.sqrt(math.log1p(c * c))
    draws = g.lognormal(math.log(m) - s * s / 2, s, (B, n)) if dist == "lognormal" else g.normal(m, m * c, (B, n))
    mb = draws.mean(1)
    return mb, np.sqrt(np.sum((draws - mb[:, None]) ** 2, 1) / (n - 1)) / mb


def _study(n_runs, seed, lab):
    """A tiny study drawn at the lab's fit: (x1, x2, y, q1)."""
    g = np.random.default_rng(seed)
    q1, q2 = _lognormal(*_fit(lab)), stats.lognorm(0.15, scale=2.0)
    x1, x2 = q1.rvs(n_runs, random_state=g), q2.rvs(n_runs, random_state=g)
    return x1, x2, x1 * x2, q1


LAB = np.random.default_rng(21).lognormal(math.log(0.3), 0.2, 10)    # n = 10 lab results


def test_lab_only_interval_is_the_closed_forms_at_the_same_lab_resamples():
    """With every run kept, each replicate is the fractile at theta*_b up to
    the weighted runs' Monte Carlo error, about sigma_y sqrt((1 + z^2/2) /
    ESS) on the logs: 20 000 runs, 400 lab resamples; the ends of the two
    intervals within 4 such errors (at the replicates' 5 % ESS).  The
    theta*_b are the test's own bootstrap's, given to both.  The
    unweighted runs, which ignore the lab's uncertainty, miss."""
    x1, x2, y, q1 = _study(20000, 22, LAB)
    boot = _own_bootstrap(LAB, "lognormal", 400, np.random.default_rng(23))
    r = D.propagate(y, {"x1": x1}, {"x1": q1}, {"x1": ("lognormal", LAB, boot)}, 24, resamples=400)
    exact = np.percentile(_exact(*boot, math.log(2.0), 0.15), [2.5, 97.5])
    sy = math.hypot(math.sqrt(math.log1p(_fit(LAB)[1] ** 2)), 0.15)
    tol = 4 * sy * math.sqrt((1 + Z ** 2 / 2) / r["ess_05"])
    assert np.abs(np.log(r["lab_only"]) - np.log(exact)).max() < tol
    assert tol < 0.2 * np.log(exact[1] / exact[0]) and r["ess_05"] > 5000
    assert r["point"] == pytest.approx(_exact(*_fit(LAB), math.log(2.0), 0.15), rel=tol)
    plain = fractiles.lognormal_fractile(y)
    assert not (abs(math.log(plain[1] / exact[0])) < tol and abs(math.log(plain[2] / exact[1])) < tol)


def test_propagated_interval_agrees_with_brute_force_reruns():
    """A tiny study, 40 runs.  Brute force reruns it from scratch at each
    of 2000 lab resamples theta*_b of the test's own bootstrap (40 new
    draws, their lognormal fractile, all by numpy); the re-weighted
    replicates resample the one study's 40 runs at the code's own lab
    resamples instead.  The one study is itself off by its Monte Carlo
    error, sigma_y sqrt((1 + z^2/2) / 40) on the logs, and carries it into
    every replicate: the intervals' ends agree within 4 such errors, and
    the widths within 30 %, closer than the interval of the lab alone or of
    the runs alone."""
    x1, x2, y, q1 = _study(40, 25, LAB)
    g = np.random.default_rng(26)
    r = D.propagate(y, {"x1": x1}, {"x1": q1}, {"x1": ("lognormal", LAB, D.lab_resamples(LAB, "lognormal", 2000, g))},
                    27, resamples=2000)
    m_b, c_b = _own_bootstrap(LAB, "lognormal", 2000, g)
    s_b = np.sqrt(np.log1p(c_b ** 2))[:, None]
    yb = g.lognormal(np.log(m_b)[:, None] - s_b ** 2 / 2, s_b, (2000, 40)) * g.lognormal(math.log(2.0), 0.15, (2000, 40))
    brute = np.percentile(_own_fractile(yb, np.ones(40)), [2.5, 97.5])
    sy = math.hypot(math.sqrt(math.log1p(_fit(LAB)[1] ** 2)), 0.15)
    tol = 4 * sy * math.sqrt((1 + Z ** 2 / 2) / 40)
    assert np.abs(np.log(r["interval"]) - np.log(brute)).max() < tol
    width = lambda ends: math.log(ends[1] / ends[0])       # noqa: E731
    assert width(r["interval"]) == pytest.approx(width(brute), rel=0.3)
    runs_only = fractiles.lognormal_fractile(y)[1:]
    miss = abs(width(r["interval"]) - width(brute))
    assert miss < abs(width(r["lab_only"]) - width(brute)) and miss < abs(width(runs_only) - width(brute))


# --- the chain against a second implementation with its own parametric bootstrap ----------------------
def _var_se(a):
    """The standard error of a sample's variance, from its fourth central moment."""
    d = a - a.mean()
    return math.sqrt((np.mean(d ** 4) - np.mean(d ** 2) ** 2) / a.size)


@pytest.mark.parametrize("dist", ["lognormal", "normal"])
def test_lab_resamples_are_the_labs_parametric_bootstrap(dist):
    """40 000 resamples of the ten lab results.  The means: mean m and
    variance (m c)^2 / n exactly (n draws of the fit's variance), within 4
    standard errors (a resample of n + 1 values has 9 % less variance, 13
    of them).  The covs: the same mean, variance and distribution as the
    test's own bootstrap's (two-sample, 4 standard errors, Kolmogorov-Smirnov
    p > 0.001); for normal draws also sqrt(n) / cov* is non-central t
    (n - 1, sqrt(n) / c), closed form."""
    B, n = 40000, LAB.size
    m_b, c_b = D.lab_resamples(LAB, dist, B, np.random.default_rng(31))
    own_m, own_c = _own_bootstrap(LAB, dist, B, np.random.default_rng(32))
    m, c = _fit(LAB)
    assert m_b.shape == c_b.shape == (B,)
    assert abs(m_b.mean() - m) < 4 * m * c / math.sqrt(n * B)
    assert abs(m_b.var(ddof=1) - (m * c) ** 2 / n) < 4 * _var_se(m_b)
    assert abs(c_b.mean() - own_c.mean()) < 4 * math.sqrt((c_b.var() + own_c.var()) / B)
    assert abs(c_b.var() - own_c.var()) < 4 * math.hypot(_var_se(c_b), _var_se(own_c))
    assert stats.ks_2samp(c_b, own_c).pvalue > 1e-3 and stats.ks_2samp(m_b, own_m).pvalue > 1e-3
    if dist == "normal":
        assert stats.kstest(c_b, lambda v: stats.nct.sf(math.sqrt(n) / v, n - 1, math.sqrt(n) / c)).pvalue > 1e-3


def _own_fractile(y, w):
    """The weighted lognormal 5 % fractile (docs, section 10): exp(m + z_0.05
    s), the weighted mean of ln y and its variance with reliability weights,
    sum w (ln y - m)^2 / (sum w - sum w^2 / sum w)."""
    ly, sw = np.log(y), w.sum(-1)
    m = (w * ly).sum(-1) / sw
    return np.exp(m + Z * np.sqrt((w * (ly - m[..., None]) ** 2).sum(-1) / (sw - (w * w).sum(-1) / sw)))


def _own_chain(y, x, q, lab, B, g):
    """The design chain of one level written again: the test's bootstrap
    theta*, the weights p(x; theta*) / q(x) with the lognormal's log density
    written out, the point at the fit, the lab-only replicates (every run)
    and both (the runs resampled by the test), Kish's ESS at the fit and of
    each replicate's resampled runs."""
    def logp(m, c):
        s = np.sqrt(np.log1p(c * c))
        return -np.log(x) - np.log(s) - 0.5 * math.log(2 * math.pi) - (np.log(x) - np.log(m) + s * s / 2) ** 2 / (2 * s * s)
    m_b, c_b = _own_bootstrap(lab, "lognormal", B, g)
    lw_hat = logp(*_fit(lab)) - q.logpdf(x)
    lw = logp(m_b[:, None], c_b[:, None]) - q.logpdf(x)
    w_hat, w = np.exp(lw_hat - lw_hat.max()), np.exp(lw - lw.max(1, keepdims=True))
    idx = g.integers(0, y.size, (B, y.size))
    w_idx = np.take_along_axis(w, idx, 1)
    return {"point": _own_fractile(y, w_hat), "ess": w_hat.sum() ** 2 / (w_hat ** 2).sum(),
            "lab_only": _own_fractile(np.broadcast_to(y, w.shape), w), "both": _own_fractile(y[idx], w_idx),
            "ess_b": w_idx.sum(1) ** 2 / (w_idx * w_idx).sum(1)}


def _quantile_se(sample, p, B):
    """The standard error of the p quantile of B draws, sqrt(p (1 - p) / B) / f,
    the density f from the sample's quantiles 0.01 either side."""
    lo, hi = max(p - 0.01, 0.0), min(p + 0.01, 1.0)
    return math.sqrt(p * (1 - p) / B) * np.diff(np.quantile(sample, [lo, hi]))[0] / (hi - lo)


def test_design_table_against_a_second_implementation_of_the_chain():
    """A study of 40 runs at two levels, drawn from a distribution wider than
    the lab's fit (cov 1.25 times, mean 1.03 times), so that the weights at
    the fit are not 1.  The point, its ESS, the design value and the
    runs-only interval (non-central t, scipy) are deterministic: to 1e-9.
    The lab-only and the whole intervals and the ESS's median and 5 %
    quantile come from 60 000 resamples on either side, independent:
    each within 4 standard errors of the difference of two such quantiles,
    and the widths within 4 of theirs (the two implementations differ by 2
    at most here).  A bootstrap of n + 1 values narrows the lab-only
    interval by 2 and 4.5 %, 5 and 8 such errors."""
    B, N = 60000, 40
    g = np.random.default_rng(35)                      # a study whose levels Shapiro-Wilk keeps lognormal
    m, c = _fit(LAB)
    q = _lognormal(1.03 * m, 1.25 * c)
    x1, x2 = q.rvs(2 * N, random_state=g), g.lognormal(math.log(2.0), 0.15, 2 * N)
    level = np.repeat([0.0, 0.1], N)
    runs = pd.DataFrame({"p_mpa": level, "x1_mpa": x1, "strength_mpa": x1 * x2 * np.where(level > 0, 1.3, 1.0),
                         "ok": True})
    t = D.design_table(runs, "p_mpa", {"x1": ("x1_mpa", 1.0)}, {"x1": q}, {"x1": ("lognormal", LAB)}, 2.5, 0.4, None,
                       0, resamples=B)
    for r, (_, group) in zip(t.itertuples(), runs.groupby("p_mpa")):
        y = group.strength_mpa.to_numpy()
        assert r.basis == "lognormal" and stats.shapiro(np.log(y)).pvalue >= 0.05
        own = _own_chain(y, group.x1_mpa.to_numpy(), q, LAB, B, g)
        assert r.f_xk_mpa == pytest.approx(own["point"], rel=1e-9) and r.ess == pytest.approx(own["ess"], rel=1e-9)
        assert r.f_xd_mpa == pytest.approx(own["point"] / 2.5, rel=1e-9) and own["ess"] < 0.98 * N
        ly, tq = np.log(y), stats.nct.ppf([0.975, 0.025], N - 1, -Z * math.sqrt(N))
        ends = np.exp(ly.mean() - tq * ly.std(ddof=1) / math.sqrt(N))
        assert (r.runs_only_lo_mpa, r.runs_only_hi_mpa) == pytest.approx(tuple(ends), rel=1e-9)
        for key, lo, hi in (("lab_only", r.lab_only_lo_mpa, r.lab_only_hi_mpa), ("both", r.f_xk_lo_mpa, r.f_xk_hi_mpa)):
            ends, se = np.percentile(own[key], [2.5, 97.5]), [_quantile_se(own[key], p, B) for p in (0.025, 0.975)]
            assert abs(lo - ends[0]) < 4 * math.sqrt(2) * se[0] and abs(hi - ends[1]) < 4 * math.sqrt(2) * se[1], key
            assert abs((hi - lo) - (ends[1] - ends[0])) < 4 * math.sqrt(2) * math.hypot(*se), key
        for value, p in ((r.ess_median, 0.5), (r.ess_05, 0.05)):
            assert abs(value - np.quantile(own["ess_b"], p)) < 4 * math.sqrt(2) * _quantile_se(own["ess_b"], p, B)


def test_the_runs_only_interval_covers_each_side_at_its_rate():
    """The runs-only interval of the design table (fractiles.lognormal_fractile,
    the same ends to 1e-9 above): 2000 studies of 20 lognormal runs, the
    true 5 % fractile below the interval in 2.5 % of them and above it in
    2.5 %, each within binomial limits (99.9 %)."""
    g, truth = np.random.default_rng(34), math.exp(math.log(1.5) + Z * 0.3)
    ends = np.array([fractiles.lognormal_fractile(g.lognormal(math.log(1.5), 0.3, 20))[1:] for _ in range(2000)])
    lo, hi = stats.binom.ppf([0.0005, 0.9995], 2000, 0.025)
    assert lo <= np.sum(truth < ends[:, 0]) <= hi and lo <= np.sum(truth > ends[:, 1]) <= hi


def test_lab_equal_to_the_studys_distribution_gives_equal_weights():
    u = np.random.default_rng(28).normal(size=10)
    lab = 0.3 * (1 + 0.2 * (u - u.mean()) / u.std(ddof=1))                 # mean 0.3, cov 0.2 exactly
    x1, _, y, q1 = _study(500, 29, lab)
    r = D.propagate(y, {"x1": x1}, {"x1": q1}, {"x1": ("normal", lab, D.lab_resamples(lab, "normal", 20, 1))}, 2,
                    resamples=20)
    assert r["ess_point"] == pytest.approx(500, rel=0.05)                   # normal lab density over a lognormal q
    r = D.propagate(y, {"x1": x1}, {"x1": D.density("normal", 0.3, 0.2)},
                    {"x1": ("normal", lab, D.lab_resamples(lab, "normal", 20, 1))}, 2, resamples=20)
    assert r["ess_point"] == pytest.approx(500) and r["point"] == pytest.approx(fractiles.lognormal_fractile(y)[0])


def test_design_table_by_hand():
    """Design value f_xk / gamma_M; AS 3700 by hand at f'_mt = 0.2, f'_ut
    = 3.0 MPa: stepped 2 sqrt(0.2) (1 + f_d / 0.2), line 0.44 x 3 + 0.56 x 0.2."""
    g = np.random.default_rng(30)
    lab = g.lognormal(math.log(0.3), 0.2, 8)
    x = D.density("lognormal", *D.moments(lab)).rvs(60, random_state=g)
    runs = pd.DataFrame({"p_mpa": np.repeat([0.0, 0.1], 30), "bond_mpa": x / 1e6 * 1e6,
                         "strength_mpa": 5 * x * np.repeat([1.0, 1.3], 30), "ok": True})
    t = D.design_table(runs, "p_mpa", {"bond": ("bond_mpa", 1.0)}, {"bond": D.density("lognormal", *D.moments(lab))},
                       {"bond": ("lognormal", lab)}, 2.5, 0.4, (0.2, 3.0), 0, resamples=200)
    assert list(t.f_xd_mpa) == pytest.approx(list(t.f_xk_mpa / 2.5)) and list(t.f_xd2_mpa) == [0.16, 0.16]
    assert list(t.as3700_stepped_mpa) == pytest.approx([2 * math.sqrt(0.2), 2 * math.sqrt(0.2) * 1.5])
    assert list(t.as3700_line_mpa) == pytest.approx([0.44 * 3 + 0.56 * 0.2] * 2)
    assert (t.f_xk_lo_mpa < t.f_xk_mpa).all() and (t.f_xk_mpa < t.f_xk_hi_mpa).all()
    assert t.equals(D.design_table(runs, "p_mpa", {"bond": ("bond_mpa", 1.0)},
                                   {"bond": D.density("lognormal", *D.moments(lab))}, {"bond": ("lognormal", lab)},
                                   2.5, 0.4, (0.2, 3.0), 0, resamples=200))            # repeatable from its seed


def test_the_worked_examples_design_table_from_its_study_file():
    """The worked example (config/studies/waal_lab.yaml, its committed runs):
    the lab records read back through the study file, EN 1996-1-1's f_xk2
    beside an interval around f_xk; at the fits the weights are 1 up to the
    study file's rounding of the mean to 4 digits, so the point is the
    study's own unweighted fractile within 1e-3 and the ESS all 20 runs."""
    from masonrydem.study.file import load_study
    study = load_study("config/studies/waal_lab.yaml")
    lab, sampling, columns, as3700 = D.study_inputs(study, "bond", "mor")
    assert {n: len(v) for n, (_, v) in lab.items()} == {"bond": 10, "mor": 7}
    assert as3700 == pytest.approx((0.2194, 3.872), rel=1e-3)       # the sheets' EN 1990 values, as recorded
    runs = pd.read_parquet("results/studies/waal_lab/study/runs.parquet")
    t = D.design_table(runs, "p_mpa", columns, sampling, lab, 2.5, D.FXK2_CLAY["general purpose, f_m >= 5 N/mm2"],
                       as3700, 0, resamples=300)
    assert list(t.f_xk2_mpa) == [0.4, 0.4] and (t.f_xk_lo_mpa < t.f_xk_mpa).all() and (t.f_xk_mpa < t.f_xk_hi_mpa).all()
    for r in t.itertuples():
        y = runs[(runs.p_mpa == r.p_mpa) & runs.ok].strength_mpa
        assert r.f_xk_mpa == pytest.approx(fractiles.lognormal_fractile(y)[0], rel=1e-3) and r.ess > 19.9
        assert r.f_xk_hi_mpa - r.f_xk_lo_mpa > r.runs_only_hi_mpa - r.runs_only_lo_mpa     # the lab adds width


def test_the_caption_gives_as3700_only_where_both_lab_values_are_fitted():
    """The worked example with the units' sheet left out of the design
    (design.units not set): no AS 3700 values in the table or its lines,
    and the caption says why, naming the missing setting; with both, the
    caption's sentence promises the values the lines show."""
    from masonrydem.study.file import load_study
    study = load_study("config/studies/waal_lab.yaml")
    runs = pd.read_parquet("results/studies/waal_lab/study/runs.parquet")
    lab, sampling, columns, as3700 = D.study_inputs(study, "bond", None)
    assert as3700 is None
    t = D.design_table(runs, "p_mpa", columns, sampling, lab, 2.5, 0.4, as3700, 0, resamples=50)
    assert "as3700_stepped_mpa" not in t and not any("AS 3700" in x for x in D.caption_lines(t, "p_mpa", "MPa"))
    words = D.as3700_words(as3700, "bond", None)
    assert "none are given" in words and "design.units (not set)" in words
    both = D.study_inputs(study, "bond", "mor")[3]
    t = D.design_table(runs, "p_mpa", columns, sampling, lab, 2.5, 0.4, both, 0, resamples=50)
    assert all("AS 3700 stepped" in x for x in D.caption_lines(t, "p_mpa", "MPa"))
    assert "at the lab's characteristic flexural bond and unit modulus of rupture do" in D.as3700_words(both)
