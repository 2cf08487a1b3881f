"""Bootstrap confidence intervals of the study's statistics and equations,
and the scorecard against the source paper, each against a
reason that does not come from the code: the normal-theory interval of a
mean, the coverage of a known distribution's mean, a second implementation
of the statistics, runs built from a known equation."""
import numpy as np
import pandas as pd
import pytest
import yaml

from masonrydem.analysis import statistics as A
from masonrydem.analysis import equations as E
from masonrydem.analysis import validation as V


def test_interval_of_a_mean_matches_normal_theory():
    """n = 400 draws of N(10, 2): the 95 % percentile-bootstrap interval of
    the mean is mean +- 1.96 s / sqrt(n) (the CLT; the bootstrap's own
    standard error is s sqrt((n-1)/n) / sqrt(n)), here to 5 % of its
    half-width with 4000 resamples."""
    x = np.random.default_rng(3).normal(10.0, 2.0, 400)
    lo, hi = A.bootstrap_interval(x.size, lambda idx: x[idx].mean(axis=-1)[None], 4000, seed=0)
    half = 1.96 * x.std(ddof=0) / np.sqrt(x.size)
    assert lo[0] == pytest.approx(x.mean() - half, abs=0.05 * half)
    assert hi[0] == pytest.approx(x.mean() + half, abs=0.05 * half)


def test_intervals_of_a_known_mean_cover_it_95_percent_of_the_time():
    """300 data sets of 60 lognormal draws (COV 0.3, like the strengths):
    the interval holds the true mean in 95 % of them, within the binomial
    spread 1.96 sqrt(0.95 0.05 / 300) = 2.5 % (and the percentile
    interval's known undercoverage at n = 60, about 1 %)."""
    rng = np.random.default_rng(7)
    s = np.sqrt(np.log(1 + 0.3 ** 2))
    true = np.exp(s ** 2 / 2)
    hits = 0
    for k in range(300):
        x = rng.lognormal(0.0, s, 60)
        lo, hi = A.bootstrap_interval(x.size, lambda idx: x[idx].mean(axis=-1)[None], 1000, seed=k)
        hits += lo[0] <= true <= hi[0]
    assert 0.95 - 0.025 - 0.01 <= hits / 300 <= 0.95 + 0.025


def _runs(n=40, seed=0, levels=(0.0, 0.25, 0.5)):
    """A constructed runs table: n samples at each level, strength rising
    with sigma_v and f_tj, the mode brick where f_tu is low."""
    rng = np.random.default_rng(seed)
    f_tj, f_tu = rng.lognormal(np.log(0.4), 0.3, n), rng.lognormal(np.log(2.0), 0.2, n)
    phi, E = rng.normal(36, 3, n), rng.lognormal(np.log(25e3), 0.2, n)
    rows = []
    for sv in levels:
        P = 10 + 8 * f_tj + 6 * sv + rng.normal(0, 0.5, n)
        brick = f_tu < np.quantile(f_tu, 0.2 + 0.8 * sv)
        rows.append(pd.DataFrame(dict(variant="nonspatial", sigma_v_mpa=sv, sample=np.arange(n),
                                      failure_mode=np.where(brick, "brick", "joint"), ok=True, P_max_kN=P,
                                      strength_mpa=0.14427 * P, f_tj_mpa=f_tj, f_tu_mpa=f_tu, phi_j_deg=phi,
                                      E_b_mpa=E)))
    runs = pd.concat(rows, ignore_index=True)
    runs.loc[3, "ok"] = False                          # one run excluded
    return runs


def test_the_resampled_statistics_at_the_sample_itself_are_the_tables(level, inputs):
    """The vectorised statistics behind the intervals (masked arrays over
    sample x level), evaluated at the sample itself, give the tables of
    ``statistics``, ``correlations`` and ``increase`` (pandas group-bys):
    two implementations, one answer."""
    runs = _runs()
    levels, d = A._wide(runs, "nonspatial", inputs, level)
    s = {k: v[0] for k, v in A._sample_statistics(d, np.arange(d["P"].shape[0])[None]).items()}
    st = A.statistics(runs, level).set_index(["mode", "sigma_v_mpa"])
    co = A.correlations(runs, inputs, level).set_index(["mode", "sigma_v_mpa"])
    inc = A.increase(A.statistics(runs, level), 0.0, 0.5, level).set_index("mode")
    for i, mode in enumerate(A.MODES):
        for j, sv in enumerate(levels):
            assert s["mean"][i, j] == pytest.approx(st.loc[(mode, sv), "P_max_mean_kN"], rel=1e-12)
            assert s["cov"][i, j] == pytest.approx(st.loc[(mode, sv), "P_max_cov"], rel=1e-12)
            assert s["strength"][i, j] == pytest.approx(st.loc[(mode, sv), "strength_mean_mpa"], rel=1e-12)
            assert s["share"][j] == pytest.approx(st.loc[(mode, sv), "brick_share"], rel=1e-12)
            assert s["r"][i, j] == pytest.approx(co.loc[(mode, sv), list(inputs)].to_numpy(float), rel=1e-10)
        assert s["increase"][i] == pytest.approx(inc.loc[mode, "increase"], rel=1e-12)


def test_intervals_hold_the_estimates_and_resample_whole_samples(level, inputs):
    """Every interval holds its estimate.  Whole samples are resampled:
    with each sample's P_max the same at every level, the mean's increase
    is 0 in every resample, so its interval is [0, 0] (resampling runs one
    by one would spread it)."""
    runs = _runs()
    st, co, inc = A.study_tables(runs, 500, 0, inputs, level)
    for table, cols in ((st, ("P_max_mean_kN", "P_max_cov", "strength_mean_mpa", "brick_share")), (co, inputs),
                        (inc, ("increase",))):
        for col in cols:
            assert table[col].notna().all()
            assert (table[f"{col}_lo"] <= table[col] + 1e-12).all() and (table[col] <= table[f"{col}_hi"] + 1e-12).all()
    flat = runs.copy()
    flat["P_max_kN"] = flat.groupby("sample").P_max_kN.transform("first")
    flat["ok"] = True
    _, _, inc = A.study_tables(flat, 200, 0, inputs, level)
    row = inc.set_index("mode").loc["all"]
    assert row.increase_lo == pytest.approx(0.0, abs=1e-12) and row.increase_hi == pytest.approx(0.0, abs=1e-12)


def test_equation_intervals_hold_the_true_coefficients(willis, columns):
    """Strengths built from a known equation plus noise (SD 0.02 MPa): the
    intervals of the refitted Lasso hold the true intercept, f_tj and
    sigma_v coefficients, and the f_tj interval is as wide as least squares
    on the same five features says (2 x 1.96 standard errors, sigma^2
    (X'X)^-1; the penalty chosen is small), within a factor of 1.5."""
    runs = _runs(n=40, seed=1)
    rng = np.random.default_rng(2)
    runs["failure_mode"] = "joint"
    runs["strength_mpa"] = 0.2 + 4.0 * runs.f_tj_mpa + 3.0 * runs.sigma_v_mpa + rng.normal(0, 0.02, len(runs))
    ok = runs[runs.ok]
    ci = E.equation_intervals(ok, willis.features, columns, resamples=200, seed=0).set_index("mode").loc["joint"]
    for term, true in (("intercept", 0.2), ("f_tj", 4.0), ("sigma_v", 3.0)):
        assert ci[f"{term}_lo"] <= true <= ci[f"{term}_hi"], (term, ci[f"{term}_lo"], ci[f"{term}_hi"])
    X = np.column_stack([np.ones(len(ok)), E.features(E.inputs_of(ok, columns), willis.features)])
    se = 0.02 * np.sqrt(np.linalg.inv(X.T @ X)[2, 2])
    assert 1 / 1.5 < (ci["f_tj_hi"] - ci["f_tj_lo"]) / (2 * 1.96 * se) < 1.5


def _two_mode_runs(seed, n, brick):
    """n samples at three levels, each run failing in the lower of a known
    joint law, 0.3 + 3 f_tj + 2 sigma_v, and the brick law ``brick``
    (intercept, f_tu and f_tj coefficients, MPa), plus an error shared by
    a sample's runs (SD 0.02 MPa) and each run's own (SD 0.01 MPa)."""
    rng = np.random.default_rng(seed)
    f_tu, f_tj = np.repeat(rng.uniform(2.0, 6.0, n), 3), np.repeat(rng.uniform(0.1, 0.8, n), 3)
    sv = np.tile([0.0, 0.25, 0.5], n)
    j, b = 0.3 + 3.0 * f_tj + 2.0 * sv, brick[0] + brick[1] * f_tu + brick[2] * f_tj
    error = np.repeat(rng.normal(0, 0.02, n), 3) + rng.normal(0, 0.01, 3 * n)
    return pd.DataFrame(dict(variant="nonspatial", ok=True, sample=np.repeat(np.arange(n), 3), sigma_v_mpa=sv,
                             f_tu_mpa=f_tu, f_tj_mpa=f_tj, failure_mode=np.where(j <= b, "joint", "brick"),
                             strength_mpa=np.minimum(j, b) + error))


def test_the_brick_coefficients_intervals_cover_their_truths_over_repeated_studies(columns):
    """60 studies of 30 samples (above; the brick law 0.2 + 0.35 f_tu + 0.2
    f_tj, about 70 % of the runs), each with 20 resamples of whole samples:
    the brick equation's intervals hold its true f_tu and f_tj coefficients
    as often as a percentile interval of 20 resamples holds the middle 95 %
    of the bootstrap distribution.  Its bounds, the 2.5 and 97.5 %
    quantiles, are interpolated between the sorted resamples at positions
    1 + 0.025 x 19 and 1 + 0.975 x 19, and the k-th of 20 sorted draws lies
    on average at probability k / 21 (order statistics of uniforms), so the
    interval holds on average (1 - 0.05) 19 / 21 = 0.860 of the bootstrap
    distribution.  Within 3 binomial standard deviations of the 120 events
    (two a study, nearly independent: f_tu and f_tj are drawn
    independently), and 0.03 more below for the percentile bootstrap's
    under-coverage on about 20 samples in the mode (the resamples spread
    about sqrt((n - 4) / n) as much as the estimate does, four coefficients
    fitted on n samples).  The intercept, whose estimate moves with the
    slopes', within the same limits of its 60 events."""
    expected = (1 - 2 * 0.025) * 19 / 21
    hits = np.zeros(3)
    terms = ("f_tu", "f_tj", "sigma_v")
    for seed in range(60):
        ns = _two_mode_runs(100 + seed, 30, (0.2, 0.35, 0.2))
        ci = E.equation_intervals(ns, terms, columns, resamples=20, seed=seed).set_index("mode").loc["brick"]
        hits += [ci[f"{t}_lo"] <= true <= ci[f"{t}_hi"] for t, true in (("intercept", 0.2), ("f_tu", 0.35), ("f_tj", 0.2))]
    slopes = (hits[1] + hits[2]) / 120
    assert expected - 0.03 - 3 * np.sqrt(expected * (1 - expected) / 120) <= slopes
    assert slopes <= expected + 3 * np.sqrt(expected * (1 - expected) / 120)
    assert abs(hits[0] / 60 - expected) <= 0.03 + 3 * np.sqrt(expected * (1 - expected) / 60)


def test_equation_intervals_do_not_depend_on_the_number_of_processes(willis, columns):
    """The refits of the bootstrap are deterministic: on two processes, in
    blocks, they give the intervals of one process to the last bit, and the
    progress reaches every resample."""
    runs = _runs(n=30, seed=5)
    ok = runs[runs.ok]
    seen = []
    one = E.equation_intervals(ok, willis.features, columns, resamples=30, seed=3)
    two = E.equation_intervals(ok, willis.features, columns, resamples=30, seed=3, jobs=2, block=12,
                               progress=lambda k, n: seen.append((k, n)))
    pd.testing.assert_frame_equal(one, two, check_exact=True)
    assert seen == [(12, 30), (24, 30), (30, 30)]


@pytest.fixture(scope="module")
def paper():
    with open("config/paper.yaml") as f:
        return yaml.safe_load(f)


def test_the_paper_equation_scores_zero_on_runs_it_generated(paper, willis, columns, level, inputs, spec):
    """Runs whose strengths are the paper's Eq. 10 itself: the scorecard
    finds the paper's equation with MAPE 0 and bias 0 on them, and says the
    paper's mean lies inside an interval that holds it."""
    runs = _runs(n=30, seed=4)
    for mode in ("joint", "brick"):
        sel = runs.failure_mode == mode
        runs.loc[sel, "strength_mpa"] = E.predict(V.paper_equation(paper, mode, willis.features),
                                                  E.inputs_of(runs[sel], columns))
    stats, _, inc = A.study_tables(runs, 100, 0, inputs, level)
    _, rows, _ = E.prediction_equations(runs[runs.ok], willis.features, columns)
    eqs = pd.DataFrame(rows).merge(E.equation_intervals(runs[runs.ok], willis.features, columns, 50, 0), on="mode",
                                   how="left")
    card = V.paper_comparison(paper, runs, stats, inc, eqs, spec, resamples=100, seed=0)
    eq10 = card[card.item.str.startswith("Eq. 10 on our runs")].set_index(["item", "mode"])
    for mode in ("joint", "brick"):
        assert eq10.loc[("Eq. 10 on our runs: MAPE (%)", mode), "ours"] == pytest.approx(0.0, abs=1e-9)
        assert eq10.loc[("Eq. 10 on our runs: bias (%)", mode), "ours"] == pytest.approx(0.0, abs=1e-9)
    assert V._card_row("x", "all", 0.0, 10.0, 11.0, 9.5, 12.0)["paper_inside"]
    assert not V._card_row("x", "all", 0.0, 10.0, 11.0, 10.5, 12.0)["paper_inside"]
    assert V._card_row("x", "all", 0.0, 10.0, 11.0, 10.5, 12.0)["difference_pct"] == pytest.approx(10.0)
