"""The direct Sobol check (analysis/sobol_check.py) on laws whose indices
are known in closed form: the Ishigami function, whose intervals must
hold its analytic indices at their rate over repeated seeds; a sum of two
correlated normals, split as the study's indices split it; SALib's own
analysis of the same outputs as a second implementation; and a
constructed comparison with a known verdict."""
import numpy as np
import pandas as pd
import pytest
from scipy import stats

from masonrydem.analysis import sobol_check as C
from masonrydem.study.copula import pick_freeze
from masonrydem.study.sampling import Variable

PI = np.pi
ISHIGAMI = [Variable(f"x{k}", "uniform", bounds=(-PI, PI)) for k in range(1, 5)]   # x4: no effect


def ishigami(x, a=7.0, b=0.1):
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_indices(a=7.0, b=0.1):
    """Sobol's and Ishigami's closed forms: V1 = (1 + b pi^4 / 5)^2 / 2,
    V2 = a^2 / 8, V13 = b^2 pi^8 (1/18 - 1/50), V = V1 + V2 + V13."""
    v1, v2, v13 = 0.5 * (1 + b * PI ** 4 / 5) ** 2, a ** 2 / 8, b ** 2 * PI ** 8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    return np.array([v1, v2, 0, 0]) / v, np.array([v1 + v13, v2, v13, 0]) / v


def test_the_design_is_pick_freeze_in_the_inputs_distributions():
    """Per base row: A, then A with column i from B for each i, then B; so
    a mixed row differs from A in column i alone and equals B there.  The
    inputs follow their marginals (Kolmogorov-Smirnov on the A rows, p >
    0.01)."""
    u, x = pick_freeze(ISHIGAMI, {}, 256, 3)
    d = 4
    u = u.reshape(-1, d + 2, d)
    a, b = u[:, 0], u[:, -1]
    for i in range(d):
        mixed = u[:, 1 + i]
        assert np.array_equal(mixed[:, i], b[:, i])
        assert np.array_equal(np.delete(mixed, i, axis=1), np.delete(a, i, axis=1))
    xa = x.reshape(-1, d + 2, d)[:, 0]
    for k in range(d):
        assert stats.kstest(xa[:, k], stats.uniform(-PI, 2 * PI).cdf).pvalue > 0.01


def test_ishigami_intervals_hold_the_analytic_indices_at_their_rate():
    """60 seeds of 256 base points (1536 runs each): each 95 % interval holds
    its analytic index in at least the binomial 99.9 % lower limit of 60
    trials at 0.95 (the bootstrap of a scrambled Sobol design is, if
    anything, conservative); x4, without effect, gets exactly 0."""
    s1, st = ishigami_indices()
    hits, seeds = np.zeros((2, 4)), 60
    for seed in range(seeds):
        _, x = pick_freeze(ISHIGAMI, {}, 256, seed + 1)
        r = C.direct_indices(ishigami(x), np.ones(len(x), bool), 4, resamples=200, seed=seed)
        hits[0] += (r["S1_lo"] <= s1) & (s1 <= r["S1_hi"])
        hits[1] += (r["ST_lo"] <= st) & (st <= r["ST_hi"])
        assert r["S1"][3] == r["ST"][3] == r["ST_lo"][3] == r["ST_hi"][3] == 0.0
    assert hits.min() >= stats.binom.ppf(0.0005, seeds, 0.95), hits


def test_a_correlated_pair_splits_as_the_studys_indices_split_it():
    """x1, x2 standard normal with rho = 0.5 (the copula of the study), y =
    x1 + x2: x1, first in order, carries the full index (1 + rho) / 2 =
    0.75, x2 its independent part (1 - rho) / 2 = 0.25 (tests/
    test_sensitivity.py works it); the direct estimates at 1024 base
    points within 0.03."""
    normals = [Variable("x1", "normal", mean=0.0, sd=1.0), Variable("x2", "normal", mean=0.0, sd=1.0)]
    _, x = pick_freeze(normals, {("x1", "x2"): 0.5}, 1024, 5)
    r = C.direct_indices(x[:, 0] + x[:, 1], np.ones(len(x), bool), 2, resamples=100)
    np.testing.assert_allclose(r["S1"], [0.75, 0.25], atol=0.03)
    np.testing.assert_allclose(r["ST"], [0.75, 0.25], atol=0.03)


def test_a_run_without_a_strength_leaves_its_base_row_out():
    """Two runs fail (rows 3 and 10): those base rows are dropped whole and
    the indices are SALib's own analysis of the other rows' outputs."""
    from SALib.analyze import sobol
    _, x = pick_freeze(ISHIGAMI, {}, 64, 7)
    y = ishigami(x)
    ok = np.ones(len(y), bool)
    ok[3 * 6 + 2] = ok[10 * 6 + 5] = False
    y[3 * 6 + 2] = np.nan
    r = C.direct_indices(y, ok, 4, resamples=100)
    assert (r["rows"], r["left_out"]) == (62, 2)
    keep = np.delete(y.reshape(64, 6), [3, 10], axis=0).ravel()
    problem = dict(num_vars=4, names=["a", "b", "c", "d"], bounds=[[0, 1]] * 4)
    ref = sobol.analyze(problem, keep, calc_second_order=False, num_resamples=10, seed=1)
    np.testing.assert_allclose(r["S1"], ref["S1"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(r["ST"], ref["ST"], rtol=1e-12, atol=1e-15)


def test_the_check_table_and_verdict_on_a_constructed_case():
    """Direct intervals (0.4 to 0.6) and (0.0 to 0.1); the study's 0.5 is
    inside, 0.15 is 0.05 above, and a missing study index is neither."""
    direct = dict(S1=np.array([0.5, 0.05]), S1_lo=np.array([0.4, 0.0]), S1_hi=np.array([0.6, 0.1]),
                  ST=np.array([0.5, 0.05]), ST_lo=np.array([0.4, 0.0]), ST_hi=np.array([0.6, 0.1]))
    study = pd.DataFrame({"S1": [0.5, 0.15], "S1_lo": [0.45, 0.1], "S1_hi": [0.55, 0.2],
                          "ST": [0.5, np.nan], "ST_lo": [0.4, np.nan], "ST_hi": [0.6, np.nan]}, index=["a", "b"])
    t = C.check_table(direct, study, ["a", "b"]).set_index("input")
    assert t.S1_inside.tolist() == [True, False] and t.S1_off.tolist() == pytest.approx([0.0, 0.05])
    assert t.loc["a", "ST_inside"] and not t.loc["b", "ST_inside"] and np.isnan(t.loc["b", "ST_off"])
    v = C.verdict(t.reset_index())
    assert v.startswith("2 of the study's 3 indices inside") and "b S1 0.150 against 0.000 to 0.100 (0.050 outside)" in v


@pytest.mark.parametrize("case", ["level", "variant"])
def test_a_check_the_study_cannot_run_is_refused_naming_its_key(case, tmp_path):
    """At planning (pipeline/check.py): a level the study does not sweep
    (0.3 MPa; the Willis study's levels are 0 to 0.5 MPa), and a study with
    no variant that draws per wallette (the Willis study with its spatial
    variant alone), are refused with the config's key; the committed
    config passes."""
    import yaml

    from masonrydem.errors import InputError
    from masonrydem.pipeline.check import check_sobol
    check_sobol(yaml.safe_load(open("config/config.yaml")))
    config = yaml.safe_load(open("config/config.yaml"))
    if case == "level":
        config["sobol_check"]["level"] = 0.3
    else:
        text = open("config/studies/willis.yaml").read().replace("  nonspatial: {draw: wallette}\n", "")
        (tmp_path / "spatial.yaml").write_text(text)
        config["study"]["file"] = str(tmp_path / "spatial.yaml")
    with pytest.raises(InputError) as e:
        check_sobol(config)
    assert e.value.field == {"level": "sobol_check.level", "variant": "sobol_check"}[case]


def test_the_intervals_are_the_percentiles_of_the_base_rows_resampled():
    """The intervals rebuilt here: the base rows resampled with replacement
    from the same seed, Saltelli's S1 and Jansen's ST written out on each
    resample of the centred, scaled outputs, their 2.5 and 97.5 %
    percentiles."""
    _, x = pick_freeze(ISHIGAMI, {}, 64, 11)
    y = ishigami(x)
    r = C.direct_indices(y, np.ones(len(y), bool), 4, resamples=50, seed=4)
    f = ((y - y.mean()) / y.std()).reshape(64, 6)
    rng, draws = np.random.default_rng(4), []
    for _ in range(50):
        g = f[rng.integers(0, 64, 64)]
        a, b, var = g[:, 0], g[:, -1], np.var(np.r_[g[:, 0], g[:, -1]])
        draws.append([[np.mean(b * (g[:, 1 + j] - a)) / var for j in range(4)],
                      [0.5 * np.mean((a - g[:, 1 + j]) ** 2) / var for j in range(4)]])
    lo, hi = np.percentile(np.array(draws), [2.5, 97.5], axis=0)
    for k, s in enumerate(("S1", "ST")):
        np.testing.assert_allclose(r[f"{s}_lo"], lo[k], rtol=1e-10, atol=1e-14)
        np.testing.assert_allclose(r[f"{s}_hi"], hi[k], rtol=1e-10, atol=1e-14)
