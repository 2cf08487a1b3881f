"""The lab's uncertainty carried to the wallette by re-weighting the runs
(analysis/design.py), against closed forms, a second implementation and
coverage: a tiny synthetic study y = x1 x2 whose 5 % fractile is
lognormal in closed form; the lab draws against the pivotal quantities'
distributions; each level's replicates against the test's own
least-squares and order-statistic code; and the interval's coverage of
the true fractile over many constructed labs and studies of 7 to 50 runs,
within binomial limits."""
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


def test_lab_only_interval_is_the_closed_forms_at_the_same_lab_draws():
    """With every run kept, each draw's fractile is the closed form's at
    theta*_b up to the weighted runs' Monte Carlo error, about sigma_y
    sqrt((1 + z^2/2) / ESS) on the logs: 20 000 runs, 400 draws of theta*
    (the test's own parametric bootstrap: any theta* will do, given to
    both); the ends of the two intervals within 4 such errors (at the
    draws' 5 % ESS).  The unweighted runs, which ignore the lab's
    uncertainty, miss."""
    x1, x2, y, q1 = _study(20000, 22, LAB)
    boot = _own_bootstrap(LAB, "lognormal", 400, np.random.default_rng(23))
    r = D.propagate(y, {"x1": x1}, {"x1": q1}, {"x1": ("lognormal", LAB, boot)}, 24)
    exact = np.percentile(_exact(*boot, math.log(2.0), 0.15), [2.5, 97.5])
    sy = math.hypot(math.sqrt(math.log1p(_fit(LAB)[1] ** 2)), 0.15)
    tol = 4 * sy * math.sqrt((1 + Z ** 2 / 2) / r["ess_05"])
    assert np.abs(np.log(r["lab_only"]) - np.log(exact)).max() < tol
    assert tol < 0.2 * np.log(exact[1] / exact[0]) and r["ess_05"] > 5000
    assert r["point"] == pytest.approx(_exact(*_fit(LAB), math.log(2.0), 0.15), rel=tol)
    plain = fractiles.lognormal_fractile(y)
    assert not (abs(math.log(plain[1] / exact[0])) < tol and abs(math.log(plain[2] / exact[1])) < tol)


# --- the lab draws: the pivotal quantities' distributions, closed form ------------------------------------
@pytest.mark.parametrize("dist", ["lognormal", "normal"])
def test_lab_draws_are_the_pivotal_quantities(dist):
    """40 000 draws from the ten lab results.  With (mu, s) the fit on the
    normal scale (lognormal: s^2 = ln(1 + c^2), mu = ln m - s^2 / 2) and
    (mu*, s*) a draw's: (n - 1) s^2 / s*^2 is chi-square with n - 1
    degrees of freedom, sqrt(n) (mu - mu*) / s* standard normal, and
    sqrt(n) (mu - (mu* + z s*)) / s non-central t (n - 1, -z sqrt(n)), the
    exact interval's distribution; each Kolmogorov-Smirnov p > 0.001."""
    n, (m, c) = LAB.size, _fit(LAB)
    m_b, c_b = D.lab_draws(LAB, dist, 40000, 31)
    if dist == "lognormal":
        s, s_b = math.sqrt(math.log1p(c * c)), np.sqrt(np.log1p(c_b ** 2))
        mu, mu_b = math.log(m) - s * s / 2, np.log(m_b) - s_b ** 2 / 2
    else:
        s, s_b, mu, mu_b = m * c, m_b * c_b, m, m_b
    assert stats.kstest((n - 1) * s * s / s_b ** 2, stats.chi2(n - 1).cdf).pvalue > 1e-3
    assert stats.kstest(math.sqrt(n) * (mu - mu_b) / s_b, stats.norm.cdf).pvalue > 1e-3
    assert stats.kstest(math.sqrt(n) * (mu - mu_b - Z * s_b) / s, stats.nct(n - 1, -Z * math.sqrt(n)).cdf).pvalue > 1e-3


# --- one level's replicates against the test's own code ---------------------------------------------------
def _own_moments(ly, U, w, EU, VU):
    """One draw's corrected mean and variance of ln y, written again: the
    weighted least-squares slopes by numpy's lstsq on the centred rows
    scaled by sqrt(w); the weighted moments with reliability weights,
    sum w (v - vbar)^2 / (sum w - sum w^2 / sum w); then m + b.(EU - Ubar)
    and the variance of ln y less the part the sample's U explains, plus
    the part the draw's U explains, b^2 VU."""
    sw, sw2 = w.sum(), (w * w).sum()
    ybar, Ubar = w @ ly / sw, w @ U / sw
    b = np.linalg.lstsq((U - Ubar) * np.sqrt(w)[:, None], (ly - ybar) * np.sqrt(w), rcond=None)[0]
    res = ly - ybar - (U - Ubar) @ b
    return ybar + b @ (EU - Ubar), w @ res ** 2 / (sw - sw2 / sw) + b ** 2 @ VU


def test_linear_replicates_against_own_least_squares_and_pivots():
    """Two lab-fitted inputs, 30 runs, unequal weights.  The lab-only
    replicates (no randomness) equal the test's own m + z s to 1e-9.
    With one weight row repeated, the runs' draws are a normal sample's
    pivotal quantities at n = ESS, drawn by the test its own way (s* from
    a gamma, m* from a normal), the two samples of 20 000 of one
    distribution (Kolmogorov-Smirnov p > 0.001).  At equal weights, with
    the draw's EU and VU the sample's own (no correction), the 2.5 and
    97.5 % percentiles are the runs-only exact interval's ends (non-central
    t) within 2 % of its width."""
    g = np.random.default_rng(40)
    n = 30
    U = np.column_stack([g.normal(0, 0.2, n), g.normal(1, 0.1, n)])
    ly = 0.3 + U @ [1.0, 0.5] + g.normal(0, 0.1, n)
    w = np.exp(g.normal(0, 0.5, (50, n)))
    EU, VU = g.normal([0, 1], 0.05, (50, 2)), np.full((50, 2), [0.04, 0.01])
    lab_only, _ = D.linear_replicates(ly, U, w, EU, VU, 0.05, 41)
    own = np.array([m + Z * math.sqrt(v) for m, v in (_own_moments(ly, U, w[b], EU[b], VU[b]) for b in range(50))])
    assert lab_only == pytest.approx(own, rel=1e-9)
    B = 20000
    _, both = D.linear_replicates(ly, U, np.broadcast_to(w[0], (B, n)), np.broadcast_to(EU[0], (B, 2)),
                                  np.broadcast_to(VU[0], (B, 2)), 0.05, 42)
    ne = w[0].sum() ** 2 / (w[0] ** 2).sum()
    m, v = _own_moments(ly, U, w[0], EU[0], VU[0])
    s_d = np.sqrt(v / (g.gamma((ne - 1) / 2, 2, B) / (ne - 1)))
    assert stats.ks_2samp(both, m - g.standard_normal(B) * s_d / math.sqrt(ne) + Z * s_d).pvalue > 1e-3
    y = np.exp(g.normal(0.2, 0.3, 12))
    U = g.normal(size=(12, 1))
    _, both = D.linear_replicates(np.log(y), U, np.ones((B, 12)), np.full((B, 1), U.mean()),
                                  np.full((B, 1), U.var(ddof=1)), 0.05, 43)
    exact = np.log(fractiles.lognormal_fractile(y)[1:])
    assert np.abs(np.percentile(both, [2.5, 97.5]) - exact).max() < 0.02 * (exact[1] - exact[0])


def test_gap_replicates_at_equal_weights_are_the_order_statistics():
    """100 runs, equal weights, 40 000 draws: the number of runs below the
    crossing K is at least j as often as a binomial (100, 0.05) count is
    (that is P(U_(j) <= p) for uniform order statistics), within 4 standard
    errors for j = 1 to 12; so the percentiles of the bounds are the
    order-statistic interval's ends (fractiles.empirical_fractile)."""
    g = np.random.default_rng(44)
    y, B = g.lognormal(0, 0.3, 100), 40000
    lower, upper = D.gap_replicates(y, np.ones((B, 100)), 0.05, 45)
    ys = np.sort(y)
    assert np.all(upper > lower) and np.all(np.isin(lower[np.isfinite(lower)], ys))
    k = np.searchsorted(ys, lower, side="right")
    for j in range(1, 13):
        p = stats.binom.sf(j - 1, 100, 0.05)
        assert abs(np.mean(k >= j) - p) < 4 * math.sqrt(p * (1 - p) / B) + 1e-12, j
    lo, hi = np.percentile(lower, 2.5, method="inverted_cdf"), np.percentile(upper, 97.5, method="inverted_cdf")
    assert (lo, hi) == fractiles.empirical_fractile(y)[1:]


def test_a_lab_known_exactly_leaves_the_runs_only_interval():
    """A lab of 200 000 results (its draws all but the fit) and 15 runs
    whose fitted input has the fit's log mean and variance exactly (the
    control variates 0): the interval is the runs-only exact interval
    (non-central t) within 3 % of its width (the percentiles of 4000
    draws); the lab-only interval all but the point."""
    g = np.random.default_rng(46)
    lab = g.lognormal(math.log(0.3), 0.2, 200000)
    q = D.density("lognormal", *D.moments(lab))
    u = g.normal(size=15)
    mu, v = D.regressor_moments("lognormal", *D.moments(lab))
    x1, y = np.exp(mu + math.sqrt(v) * (u - u.mean()) / u.std(ddof=1)), g.lognormal(0.5, 0.25, 15)
    r = D.propagate(y, {"x1": x1}, {"x1": q}, {"x1": ("lognormal", lab, D.lab_draws(lab, "lognormal", 4000, g))}, 47)
    _, lo, hi = fractiles.lognormal_fractile(y)
    assert r["interval"] == pytest.approx((lo, hi), abs=0.03 * (hi - lo))
    assert r["lab_only"] == pytest.approx((r["point"], r["point"]), abs=0.03 * (hi - lo))


# --- coverage: the interval against the true fractile, over constructed labs and studies ------------------
def _coverage(basis, n_runs, n_lab, sd2, reps, seed):
    """(below, above): how often the true 5 % fractile of y = x1 x2 falls
    below or above the design interval.  The truth: x1 lognormal of mean
    0.3 and cov 0.2, ln x2 normal (ln 2, sd2).  Each repetition draws a lab
    of n_lab results from it, fits it (the study's q), draws a study of
    n_runs from q and the truth's x2, and takes its interval (400 draws)."""
    g = np.random.default_rng(seed)
    s1 = math.sqrt(math.log1p(0.04))
    truth = math.exp(math.log(0.3) - s1 * s1 / 2 + math.log(2.0) + Z * math.hypot(s1, sd2))
    below = above = 0
    for _ in range(reps):
        lab = g.lognormal(math.log(0.3) - s1 * s1 / 2, s1, n_lab)
        q = D.density("lognormal", *D.moments(lab))
        x1 = q.rvs(n_runs, random_state=g)
        y = x1 * g.lognormal(math.log(2.0), sd2, n_runs)
        r = D.propagate(y, {"x1": x1}, {"x1": q}, {"x1": ("lognormal", lab, D.lab_draws(lab, "lognormal", 400, g))},
                        g, basis)
        lo, hi = r["interval"]
        below += bool(truth < lo)
        above += bool(truth > hi)
    return below, above


@pytest.mark.parametrize("n_lab, sd2", [(10, 0.15), (5, 0.02), (30, 0.3)],
                         ids=["lab and runs", "lab dominates", "runs dominate"])
@pytest.mark.parametrize("n_runs", [7, 10, 20, 50])
def test_the_interval_covers_the_true_fractile(n_runs, n_lab, sd2):
    """300 constructed labs and studies per case (lognormal strengths):
    the interval misses the true fractile on each side at most as often as
    the binomial (300, 2.5 %) allows (99.9 %): it is never narrower than
    its evidence.  (Where the lab dominates at few runs it is wider than it
    need be: the runs' pivot is applied to the whole variance.)"""
    below, above = _coverage("lognormal", n_runs, n_lab, sd2, 300, [n_runs, n_lab])
    assert max(below, above) <= stats.binom.ppf(0.999, 300, 0.025), (below, above)


@pytest.mark.parametrize("n_runs", [7, 20, 50, 100])
def test_the_distribution_free_interval_covers_the_true_fractile(n_runs):
    """The non-parametric basis on the same lab-and-runs case: each side's
    misses within the binomial (300, 2.5 %) limit; below 72 runs no lower
    end exists (the order statistics' rule) and the interval says so."""
    below, above = _coverage("non-parametric", n_runs, 10, 0.15, 300, [n_runs, 1])
    assert max(below, above) <= stats.binom.ppf(0.999, 300, 0.025), (below, above)
    if n_runs < 72:
        assert below == 0


def test_design_table_against_a_second_implementation_of_its_point():
    """A study of 40 runs at two levels, drawn from a distribution wider than
    the lab's fit (cov 1.25 times, mean 1.03 times), so that the weights at
    the fit are not 1.  The point (the weighted lognormal fractile with the
    lognormal's log density written out), its ESS, the design value and the
    runs-only interval (non-central t, scipy) against the test's own: to
    1e-9."""
    N = 40
    g = np.random.default_rng(35)
    m, c = _fit(LAB)
    q = _lognormal(1.03 * m, 1.25 * c)
    x1, x2 = q.rvs(2 * N, random_state=g), g.lognormal(math.log(2.0), 0.15, 2 * N)
    level = np.repeat([0.0, 0.1], N)
    runs = pd.DataFrame({"p_mpa": level, "x1_mpa": x1, "strength_mpa": x1 * x2 * np.where(level > 0, 1.3, 1.0),
                         "ok": True})
    t = D.design_table(runs, "p_mpa", {"x1": ("x1_mpa", 1.0)}, {"x1": q}, {"x1": ("lognormal", LAB)}, 2.5, 0.4, None,
                       0, draws=200)
    s = math.sqrt(math.log1p(c * c))
    for r, (_, group) in zip(t.itertuples(), runs.groupby("p_mpa")):
        y, x = group.strength_mpa.to_numpy(), group.x1_mpa.to_numpy()
        assert r.basis == "lognormal" and stats.shapiro(np.log(y)).pvalue >= 0.05
        logp = -np.log(x * s * math.sqrt(2 * math.pi)) - (np.log(x) - math.log(m) + s * s / 2) ** 2 / (2 * s * s)
        lw = logp - q.logpdf(x)
        w = np.exp(lw - lw.max())
        ly, sw = np.log(y), w.sum()
        mean = (w * ly).sum() / sw
        point = math.exp(mean + Z * math.sqrt((w * (ly - mean) ** 2).sum() / (sw - (w * w).sum() / sw)))
        assert r.f_xk_mpa == pytest.approx(point, rel=1e-9) and r.ess == pytest.approx(sw ** 2 / (w * w).sum(), rel=1e-9)
        assert r.f_xd_mpa == pytest.approx(point / 2.5, rel=1e-9) and r.ess < 0.98 * N
        tq = stats.nct.ppf([0.975, 0.025], N - 1, -Z * math.sqrt(N))
        ends = np.exp(ly.mean() - tq * ly.std(ddof=1) / math.sqrt(N))
        assert (r.runs_only_lo_mpa, r.runs_only_hi_mpa) == pytest.approx(tuple(ends), rel=1e-9)


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
    r = D.propagate(y, {"x1": x1}, {"x1": q1}, {"x1": ("normal", lab, D.lab_draws(lab, "normal", 20, 1))}, 2)
    assert r["ess_point"] == pytest.approx(500, rel=0.05)                   # normal lab density over a lognormal q
    r = D.propagate(y, {"x1": x1}, {"x1": D.density("normal", 0.3, 0.2)},
                    {"x1": ("normal", lab, D.lab_draws(lab, "normal", 20, 1))}, 2)
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
                       {"bond": ("lognormal", lab)}, 2.5, 0.4, (0.2, 3.0), 0, draws=200)
    assert list(t.f_xd_mpa) == pytest.approx(list(t.f_xk_mpa / 2.5)) and list(t.f_xd2_mpa) == [0.16, 0.16]
    assert list(t.as3700_stepped_mpa) == pytest.approx([2 * math.sqrt(0.2), 2 * math.sqrt(0.2) * 1.5])
    assert list(t.as3700_line_mpa) == pytest.approx([0.44 * 3 + 0.56 * 0.2] * 2)
    assert (t.f_xk_lo_mpa < t.f_xk_mpa).all() and (t.f_xk_mpa < t.f_xk_hi_mpa).all()
    assert t.equals(D.design_table(runs, "p_mpa", {"bond": ("bond_mpa", 1.0)},
                                   {"bond": D.density("lognormal", *D.moments(lab))}, {"bond": ("lognormal", lab)},
                                   2.5, 0.4, (0.2, 3.0), 0, draws=200))            # repeatable from its seed


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
                       as3700, 0, draws=300)
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
    t = D.design_table(runs, "p_mpa", columns, sampling, lab, 2.5, 0.4, as3700, 0, draws=50)
    assert "as3700_stepped_mpa" not in t and not any("AS 3700" in x for x in D.caption_lines(t, "p_mpa", "MPa"))
    words = D.as3700_words(as3700, "bond", None)
    assert "none are given" in words and "design.units (not set)" in words
    both = D.study_inputs(study, "bond", "mor")[3]
    t = D.design_table(runs, "p_mpa", columns, sampling, lab, 2.5, 0.4, both, 0, draws=50)
    assert all("AS 3700 stepped" in x for x in D.caption_lines(t, "p_mpa", "MPa"))
    assert "at the lab's characteristic flexural bond and unit modulus of rupture do" in D.as3700_words(both)


def test_the_design_caption_gives_each_lab_value_beside_the_models():
    """The worked example's two lab-fitted variables: the lab's mean times
    the conversion factor is the model's mean the study draws from (to
    the study file's 4 digits), and the caption's words give all three."""
    import re
    from masonrydem.study.file import load_study
    words = D.lab_words(load_study("config/studies/waal_lab.yaml"))
    found = re.findall(r"(\w+), (\d+) results of the lab's ([\w ]+), mean ([\d.]+) MPa x ([\d.]+) \(EN 1992-1-1:2004\) "
                       r"= the model's mean ([\d.]+) MPa", words)
    assert [f[:3] for f in found] == [("bond", "10", "flexural bond strength"), ("mor", "7", "modulus of rupture")]
    for *_, lab, factor, model in found:
        assert float(lab) * float(factor) == pytest.approx(float(model), rel=3e-4)


def test_the_docs_rerun_table_is_the_committed_rerun():
    """docs/lab-to-design.md's table of the solver reruns is rerun.csv row by
    row, and every re-weighted fractile lies inside its rerun's interval."""
    import re
    from pathlib import Path
    t = pd.read_csv("results/studies/waal_lab/design/rerun.csv", dtype=str)
    text = Path("docs/lab-to-design.md").read_text()
    for r in t.itertuples():
        row = (f"| {r.p_mpa} | {r.draw} ({r.lab_quantile} %) | {r.bond_mean_mpa} MPa, {r.bond_cov} | {r.mor_mean_mpa} "
               f"MPa, {r.mor_cov} | {r.reweighted_mpa} | {r.ess} | {r.rerun_mpa} ({r.rerun_lo_mpa} to "
               f"{r.rerun_hi_mpa}) |")
        assert row in text, row
        assert float(r.rerun_lo_mpa) <= float(r.reweighted_mpa) <= float(r.rerun_hi_mpa)
    assert len(re.findall(r"^\| 0\.?2? \| \d+ \(", text, re.M)) == len(t)
