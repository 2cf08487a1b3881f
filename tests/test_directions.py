"""Both bending directions' statistics against known answers: the mean's
interval and Fieller's interval of the orthogonal ratio cover the truth
at their confidence on constructed pairs, and the pairing keeps only
samples whose runs are ok in both directions."""
import numpy as np
import pandas as pd
import pytest
from scipy import stats

from masonrydem.analysis.directions import directions_table, mean_interval, paired, ratio_interval


def _coverage(n, rho, cases=2000, seed=1):
    """Share of ``cases`` whose intervals hold the true mean of f_x1 and
    the true mu: bivariate normal pairs, f_x2 ~ N(1.0, 0.2), f_x1 ~
    N(0.4, 0.1), correlation rho (the same material in both)."""
    rng = np.random.default_rng(seed)
    mean, sd = np.array([0.4, 1.0]), np.array([0.1, 0.2])
    cov = np.outer(sd, sd) * np.array([[1.0, rho], [rho, 1.0]])
    hit_mean = hit_mu = 0
    for _ in range(cases):
        x = rng.multivariate_normal(mean, cov, size=n)
        _, lo, hi = mean_interval(x[:, 0])
        hit_mean += lo <= 0.4 <= hi
        _, lo, hi = ratio_interval(x[:, 0], x[:, 1])
        hit_mu += lo <= 0.4 <= hi
    return hit_mean / cases, hit_mu / cases


@pytest.mark.parametrize("n, rho", [(7, 0.0), (20, 0.6), (100, 0.9), (20, -0.5)])
def test_the_intervals_cover_at_their_confidence(n, rho):
    """95 % intervals over 2000 constructed studies cover 95 % within the
    binomial limits of 2000 cases (p = 0.001 each side: 93.5 to 96.5 %)."""
    lo, hi = stats.binom.ppf([0.001, 0.999], 2000, 0.95) / 2000
    mean, mu = _coverage(n, rho)
    assert lo <= mean <= hi and lo <= mu <= hi, (mean, mu, lo, hi)


def test_fieller_narrows_with_the_pairs_correlation():
    """Positively correlated pairs (one material in both directions) give
    a narrower ratio interval than the same margins uncorrelated: what a
    paired study gains over two independent ones."""
    rng = np.random.default_rng(3)
    z = rng.standard_normal((2, 30))
    y = 1.0 + 0.2 * z[0]
    x_corr = 0.4 + 0.1 * (0.9 * z[0] + np.sqrt(1 - 0.81) * z[1])
    x_ind = 0.4 + 0.1 * z[1]
    width = [np.subtract(*ratio_interval(x, y)[2:0:-1]) for x in (x_corr, x_ind)]
    assert width[0] < 0.6 * width[1]


def test_a_ratio_over_a_mean_near_zero_has_no_bounded_interval():
    x, y = np.array([1.0, 1.1, 0.9, 1.05]), np.array([0.1, -0.1, 0.05, -0.02])
    assert np.isnan(ratio_interval(x, y)[1])


def test_pairs_need_both_runs_ok():
    """A sample whose run failed in one direction is no pair; the others
    pair on variant, sample and level."""
    base = dict(variant="v", p_mpa=0.0)
    h = pd.DataFrame([{**base, "sample": s, "strength_mpa": 1.0 + s, "ok": s != 2} for s in range(4)])
    v = pd.DataFrame([{**base, "sample": s, "strength_mpa": 0.3 + s, "ok": s != 0} for s in range(4)])
    p = paired(h, v, "p_mpa")
    assert p["sample"].tolist() == [1, 3] and p.f_x1.tolist() == [1.3, 3.3] and p.f_x2.tolist() == [2.0, 4.0]
    t = directions_table(p, "p_mpa")
    assert t.loc[0, "pairs"] == 2 and t.loc[0, "mu"] == pytest.approx(4.6 / 6.0)
