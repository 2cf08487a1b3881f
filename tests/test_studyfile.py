"""A study defined in a file.  The Willis study file gives the
committed samples bit for bit; each distribution draws its known
marginal; bad study files are refused naming the field."""
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from scipy import stats

from masonrydem.errors import InputError
from masonrydem.study.sampling import Variable, lhs, records
from masonrydem.study.file import load_study

WILLIS = "config/studies/willis.yaml"


def test_the_willis_study_file_is_the_study_of_docs_study_md():
    """Against docs/study.md, section 6 (Table 2 of the source): the
    marginals by mean and COV in SI, E_b and f_tu correlated 0.5, and the
    rules of section 3 (G_I = 0.03 N/mm per MPa of f_tj, G_fu = 0.04
    f_tu^0.7)."""
    s = load_study(WILLIS)
    table2 = {"f_tj": ("lognormal", 0.30e6, 0.40, "materials.joints.ft", "joint"),
              "f_tu": ("lognormal", 3.75e6, 0.25, "materials.units.ft", "unit"),
              "phi_j": ("normal", 35.0, 0.10, "materials.joints.phi", "joint"),
              "E_b": ("lognormal", 15000e6, 0.30, "materials.units.E", "unit")}
    assert s.variables == tuple(Variable(n, d, m, c, setting=st, per=p) for n, (d, m, c, st, p) in table2.items())
    assert s.correlations == {("E_b", "f_tu"): 0.5}
    assert (s.samples, s.seed) == (100, 20260101)
    assert s.variants == {"nonspatial": {"draw": "wallette", "correlation_length": None},
                          "spatial": {"draw": "items", "correlation_length": None}}
    assert s.levels == (0.0, 0.075e6, 0.15e6, 0.25e6, 0.5e6)
    assert s.rules["materials.joints.GI_per_ft"] == 0.03 * 1e3 / 1e6
    assert s.rules["materials.units.Gf_rule"] == {"coefficient": 0.04, "exponent": 0.7}
    assert s.regression_variant == "nonspatial" and s.features == ("f_tu", "f_tj", "f_tu^2", "f_tj^2", "sigma_v")


def test_the_willis_study_file_draws_the_committed_samples_bit_for_bit():
    """The committed results are this study file's: it draws their samples
    bit for bit.  And what it draws is what it says (Table 2 of the source
    paper, as the file writes it): a Latin Hypercube of the wallettes, one
    value in each of the 100 strata of every variable (its CDF values
    (k + u) / 100), each variable's mean and COV as written (to the
    sampling error of 100 stratified values), and E_b with f_tu at the
    correlation 0.5 (within 0.1)."""
    s = load_study(WILLIS)
    for name in ("nonspatial", "spatial"):
        committed = records(pd.read_parquet(f"results/study/samples_{name}.parquet"))
        assert records(s.draw(name).table) == committed
    d = pd.read_parquet("results/study/samples_nonspatial.parquet")
    assert len(d) == s.samples == 100
    for v in s.variables:
        u = v.frozen().cdf(d[v.name].to_numpy())
        assert sorted(np.floor(u * 100).astype(int)) == list(range(100)), v.name
        assert d[v.name].mean() == pytest.approx(v.mean, rel=0.01), v.name
        assert d[v.name].std() / d[v.name].mean() == pytest.approx(v.cov, rel=0.05), v.name
    assert stats.spearmanr(d.E_b, d.f_tu)[0] == pytest.approx(0.5, abs=0.1)


@pytest.mark.parametrize("var,mean,sd,lo,hi", [
    (Variable("x", "uniform", bounds=(2.0, 6.0)), 4.0, 4.0 / np.sqrt(12), 2.0, 6.0),
    (Variable("x", "normal", mean=10.0, sd=2.0), 10.0, 2.0, -np.inf, np.inf),
    (Variable("x", "normal", mean=10.0, cov=0.2), 10.0, 2.0, -np.inf, np.inf),
    # a normal cut symmetrically at +-1 sd: sd = sqrt(1 - 2 phi(1) / (2 Phi(1) - 1)) of the parent's
    (Variable("x", "truncated_normal", mean=10.0, sd=2.0, bounds=(8.0, 12.0)), 10.0,
     2.0 * np.sqrt(1 - 2 * stats.norm.pdf(1) / (2 * stats.norm.cdf(1) - 1)), 8.0, 12.0),
    (Variable("x", "lognormal", mean=3.0, cov=0.25), 3.0, 0.75, 0.0, np.inf),
])
def test_each_distribution_draws_its_marginal(var, mean, sd, lo, hi):
    """A Latin Hypercube of 20,000 puts one value in each stratum: the
    sample's mean and sd are the distribution's to a fraction of a percent."""
    x = lhs(20_000, [var], correlations={}, seed=3)[0]["x"]
    assert x.min() >= lo and x.max() <= hi
    assert x.mean() == pytest.approx(mean, rel=2e-3)
    assert x.std() == pytest.approx(sd, rel=1e-2)


def test_a_lognormal_cut_to_bounds_stays_inside_them():
    x = lhs(5_000, [Variable("x", "lognormal", mean=3.0, cov=0.5, bounds=(2.0, 4.0))], correlations={}, seed=1)[0]["x"]
    assert 2.0 <= x.min() and x.max() <= 4.0
    # one value per stratum of the cut distribution: its quantiles are the sample's
    F = stats.lognorm(s=np.sqrt(np.log(1.25)), scale=3.0 / np.sqrt(1.25))
    u = (F.cdf(np.sort(x)) - F.cdf(2.0)) / (F.cdf(4.0) - F.cdf(2.0))
    assert np.all(np.floor(u * 5000) == np.arange(5000))


def _study(tmp_path, **change):
    data = yaml.safe_load(Path(WILLIS).read_text())
    for key, value in change.items():
        node = data
        *head, last = key.split("__")
        for k in head:
            node = node[k]
        if value is None:
            del node[last]
        else:
            node[last] = value
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


@pytest.mark.parametrize("change,field,words", [
    (dict(samples=0), "study.samples", "minimum"),
    (dict(variables__f_tj__setting="materials.joints.fx"), "study.variables.f_tj.setting", "not a numeric setting"),
    (dict(variables__f_tj__mean="0.3 mm"), "study.variables.f_tj.mean", "a length"),
    (dict(variables__f_tj__mean=0.3), "study.variables.f_tj.mean", "has no unit"),
    (dict(variables__f_tj__mean=0.3), "study.variables.f_tj.mean", "did you mean '0.3 MPa'?"),
    (dict(variables__f_tj__cov=None, variables__f_tj__sd=0.1), "study.variables.f_tj.sd", "did you mean '0.1 MPa'?"),
    (dict(variables__f_tj__cov=3), "study.variables.f_tj.cov", "lies in (0, 1]"),
    (dict(variables__f_tj__mean="-0.3 MPa"), "study.variables.f_tj.mean", "mean is above 0"),
    (dict(variables__f_tj__distribution="truncated_normal", variables__f_tj__bounds=["0.5 MPa", "0.1 MPa"]),
     "study.variables.f_tj.bounds", "min must be below max"),
    (dict(variables__f_tj__settting="materials.joints.ft"), "study.variables.f_tj.settting",
     "did you mean 'setting'?"),
    (dict(variables__f_tj__setting="materials.joint.ft"), "study.variables.f_tj.setting",
     "did you mean 'materials.joints.ft'?"),
    (dict(varaibles={}), "study.varaibles", "did you mean 'variables'?"),
    (dict(correlations=[{"between": ["E_b", "E_b"], "rho": 0.5}]), "study.correlations.0.between", "with itself"),
    (dict(correlations=[{"between": ["E_b", "f_tu"], "rho": 0.5}, {"between": ["f_tu", "E_b"], "rho": -0.5}]),
     "study.correlations.1", "correlated twice"),
    (dict(correlations=[{"between": ["E_b", "f_tu"], "rho": 0.9}, {"between": ["f_tu", "f_tj"], "rho": 0.9},
                        {"between": ["E_b", "f_tj"], "rho": -0.9}]), "study.correlations", "not positive definite"),
    (dict(samples=5), "study.samples", "at least 7"),
    (dict(variables__f_tj__distribution="uniform"), "study.variables.f_tj", "needs bounds"),
    (dict(variables__f_tj__cov=None), "study.variables.f_tj", "one of cov or sd"),
    (dict(variables__f_tj__per="brick"), "study.variables.f_tj.per", "is not one of"),
    (dict(correlations=[{"between": ["E_b", "f_x"], "rho": 0.5}]), "study.correlations.0.between.1", "not a variable"),
    (dict(variants__spatial__draw="grid"), "study.variants.spatial.draw", "is not one of"),
    (dict(variants__spatial__draw="field"), "study.variants.spatial.correlation_length", "needs its correlation length"),
    (dict(variants__spatial__correlation_length="0.3 m"), "study.variants.spatial.correlation_length", "only a field"),
    (dict(variants__spatial={"draw": "field", "correlation_length": "300 MPa"}),
     "study.variants.spatial.correlation_length", "a stress"),
    (dict(sweep__levels=["0 MPa", "0.15"]), "study.sweep.levels.1", "did you mean '0.15 MPa'?"),
    (dict(sweep__levels=["0 MPa", "0.1 N/mm2", "100 kPa"]), "study.sweep.levels.2",
     "'100 kPa' is the level '0.1 N/mm2' (sweep.levels.1) again: give each level once"),
    (dict(variables__f_tj__distribution="normal", variables__f_tj__mean="0 MPa"), "study.variables.f_tj.mean",
     "a cov (sd / mean) needs a mean above 0; give sd instead"),
    (dict(rules={"materials.joints.GI_per_ft": 0.03}), "study.rules.materials.joints.GI_per_ft",
     "did you mean '0.03 mm'?"),
    (dict(scene="config/scenes/none.yaml"), "study.scene", "cannot read"),
    (dict(regression={"features": ["f_tu", "f_x^2"]}), "study.regression.features.1", "'f_x' in 'f_x^2' is not an input"),
    (dict(regression={"features": ["f_tu^"]}), "study.regression.features.0", "is not an arithmetic expression"),
    (dict(regression={"features": ["f_tu.real"]}), "study.regression.features.0", "only inputs, numbers"),
    (dict(regression={"features": ["2^3"]}), "study.regression.features.0", "uses no input"),
    (dict(sweep__name="f_tj"), "study.sweep.name", "a variable's name too"),
])
def test_a_bad_study_file_is_refused_naming_the_field(tmp_path, change, field, words):
    with pytest.raises(InputError) as e:
        load_study(_study(tmp_path, **change))
    assert e.value.field == field and words in e.value.reason, str(e.value)


def test_a_field_variant_reads_its_correlation_length_in_any_length_unit(tmp_path):
    s = load_study(_study(tmp_path, variants__spatial={"draw": "field", "correlation_length": "300 mm"}))
    assert s.variants["spatial"] == {"draw": "field", "correlation_length": 0.3}


def test_the_inputs_columns_and_terms_of_a_study(tmp_path):
    """Each input (a variable, or the sweep by its name) has the runs
    table's column of its name and the unit it is shown in; the terms
    are arithmetic expressions of inputs (the names they use; their values
    by hand); without a regression, each input enters linearly."""
    import numpy as np
    from masonrydem.study.terms import evaluate_term, parse_term
    s = load_study(WILLIS)
    assert s.columns() == dict(f_tj="f_tj_mpa", f_tu="f_tu_mpa", phi_j="phi_j_deg", E_b="E_b_mpa", sigma_v="sigma_v_mpa")
    assert s.features == ("f_tu", "f_tj", "f_tu^2", "f_tj^2", "sigma_v") and s.level_column() == "sigma_v_mpa"
    assert s.means() == dict(f_tj=0.3, f_tu=3.75, phi_j=35.0, E_b=15000.0)
    assert parse_term("f_tj^2 * sigma_v", s.units)[1] == ("f_tj", "sigma_v")
    x = dict(f_tj=np.array([0.2, 0.4]), sigma_v=np.array([0.5, 0.1]), f_tu=np.array([3.0, 4.0]))
    np.testing.assert_array_equal(evaluate_term("f_tj^2 * sigma_v", x), [0.2 ** 2 * 0.5, 0.4 ** 2 * 0.1])
    np.testing.assert_array_equal(evaluate_term("-f_tj*(f_tu + 1)/(2*sigma_v)", x),
                                  [-0.2 * 4.0 / 1.0, -0.4 * 5.0 / 0.2])
    t = load_study(_study(tmp_path, sweep={"setting": "geometry.joint_thickness", "levels": ["10 mm", "12 mm"]},
                          regression=None))
    assert (t.sweep_name, t.level_column(), t.levels) == ("joint_thickness", "joint_thickness_mm", (0.01, 0.012))
    assert t.features == tuple(v.name for v in t.variables) + ("joint_thickness",)


def test_the_regression_variant_is_the_first_that_draws_per_wallette(tmp_path):
    """Not given: the first variant drawing one value per wallette (here
    the second); given, it must draw so."""
    s = load_study(_study(tmp_path, variants={"fields": {"draw": "items"}, "walls": {"draw": "wallette"}}))
    assert list(s.variants) == ["fields", "walls"] and s.regression_variant == "walls"
    with pytest.raises(InputError) as e:
        load_study(_study(tmp_path, regression={"variant": "spatial"}))
    assert e.value.field == "study.regression.variant" and "per wallette" in e.value.reason


def test_the_wallette_of_mean_properties_takes_each_variables_mean():
    """Its settings: the rules, and each variable at the mean the file
    gives (Table 2's, in SI: a lognormal's mean, not its median)."""
    s = load_study(WILLIS)
    m = s.mean_settings()
    assert {k: m[k] for k in ("materials.joints.ft", "materials.units.ft", "materials.joints.phi",
                              "materials.units.E")} == {"materials.joints.ft": 0.30e6, "materials.units.ft": 3.75e6,
                                                        "materials.joints.phi": 35.0, "materials.units.E": 15e9}
    assert m["materials.joints.GI_per_ft"] == s.rules["materials.joints.GI_per_ft"]
