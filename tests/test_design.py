"""The lab's uncertainty carried to the wallette by re-weighting the runs
(analysis/design.py), against closed forms and brute force: a tiny
synthetic study y = x1 x2 whose 5 % fractile is lognormal in closed form,
rerun from scratch at every resampled lab fit."""
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


def _study(n_runs, seed, lab):
    """A tiny study drawn at the lab's fit: (x1, x2, y, q1, q2)."""
    g = np.random.default_rng(seed)
    q1, q2 = D.density("lognormal", *D.moments(lab)), stats.lognorm(0.15, scale=2.0)
    x1, x2 = q1.rvs(n_runs, random_state=g), q2.rvs(n_runs, random_state=g)
    return x1, x2, x1 * x2, q1


LAB = np.random.default_rng(21).lognormal(math.log(0.3), 0.2, 10)    # n = 10 lab results


def test_lab_only_interval_is_the_closed_forms_at_the_same_lab_resamples():
    """With every run kept, each replicate is the fractile at theta*_b up to
    the weighted runs' Monte Carlo error, about sigma_y sqrt((1 + z^2/2) /
    ESS) on the logs: 20 000 runs, 400 lab resamples; the ends of the two
    intervals within 4 such errors (at the replicates' 5 % ESS).  The
    unweighted runs, which ignore the lab's uncertainty, miss."""
    x1, x2, y, q1 = _study(20000, 22, LAB)
    boot = D.lab_resamples(LAB, "lognormal", 400, np.random.default_rng(23))
    r = D.propagate(y, {"x1": x1}, {"x1": q1}, {"x1": ("lognormal", LAB, boot)}, 24, resamples=400)
    exact = np.percentile(_exact(*boot, math.log(2.0), 0.15), [2.5, 97.5])
    sy = math.hypot(math.sqrt(math.log1p(D.moments(LAB)[1] ** 2)), 0.15)
    tol = 4 * sy * math.sqrt((1 + Z ** 2 / 2) / r["ess_05"])
    assert np.abs(np.log(r["lab_only"]) - np.log(exact)).max() < tol
    assert tol < 0.2 * np.log(exact[1] / exact[0]) and r["ess_05"] > 5000
    assert r["point"] == pytest.approx(_exact(*D.moments(LAB), math.log(2.0), 0.15), rel=tol)
    plain = fractiles.lognormal_fractile(y)
    assert not (abs(math.log(plain[1] / exact[0])) < tol and abs(math.log(plain[2] / exact[1])) < tol)


def test_propagated_interval_agrees_with_brute_force_reruns():
    """A tiny study, 40 runs.  Brute force reruns it from scratch at each
    of 2000 lab resamples theta*_b (40 new draws, their lognormal fractile);
    the re-weighted replicates resample the one study's 40 runs instead.
    The one study is itself off by its Monte Carlo error, sigma_y sqrt((1 +
    z^2/2) / 40) on the logs, and carries it into every replicate: the
    intervals' ends agree within 4 such errors, and the widths within 30 %,
    closer than the interval of the lab alone or of the runs alone."""
    x1, x2, y, q1 = _study(40, 25, LAB)
    g = np.random.default_rng(26)
    m_b, c_b = D.lab_resamples(LAB, "lognormal", 2000, g)
    r = D.propagate(y, {"x1": x1}, {"x1": q1}, {"x1": ("lognormal", LAB, (m_b, c_b))}, 27, resamples=2000)
    x1b = D.density("lognormal", m_b[:, None], c_b[:, None]).rvs(size=(2000, 40), random_state=g)
    yb = x1b * stats.lognorm(0.15, scale=2.0).rvs(size=(2000, 40), random_state=g)
    brute = np.percentile(D.weighted_fractile(yb, np.ones(40), 0.05, "lognormal"), [2.5, 97.5])
    sy = math.hypot(math.sqrt(math.log1p(D.moments(LAB)[1] ** 2)), 0.15)
    tol = 4 * sy * math.sqrt((1 + Z ** 2 / 2) / 40)
    assert np.abs(np.log(r["interval"]) - np.log(brute)).max() < tol
    width = lambda ends: math.log(ends[1] / ends[0])       # noqa: E731
    assert width(r["interval"]) == pytest.approx(width(brute), rel=0.3)
    runs_only = fractiles.lognormal_fractile(y)[1:]
    miss = abs(width(r["interval"]) - width(brute))
    assert miss < abs(width(r["lab_only"]) - width(brute)) and miss < abs(width(runs_only) - width(brute))


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
