"""``masonrydem check`` (a scene validated and estimated, nothing
built or run) and ``masonrydem predict`` (a study's equations as a tool),
the latter on synthetic runs whose strengths follow known equations."""
import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from masonrydem.errors import InputError
from masonrydem.pipeline import check
from masonrydem.analysis import equations, predict
from masonrydem.specimen import protocol, build as specimen
from masonrydem.scene import build_scene
from masonrydem.scene import model_size

WILLIS = "config/scenes/willis.yaml"


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "masonrydem.cli", *args], capture_output=True, text=True)


def test_check_counts_the_model_and_builds_nothing(monkeypatch, capsys):
    from masonrydem import cli

    def refuse(*a, **k):
        raise AssertionError("check built or ran a model")
    monkeypatch.setattr(specimen, "build", refuse)
    monkeypatch.setattr(protocol, "simulate", refuse)
    assert cli.main(["check", WILLIS, "--set", "numerics.cells=[4, 2, 2]"]) == 0
    out = capsys.readouterr().out
    scene = build_scene(WILLIS, ["numerics.cells=[4, 2, 2]"])
    size = model_size(scene.geometry, scene.physics, scene.discretization, scene.loading)
    assert f"{size['nodes']:,} nodes" in out and f"{size['sub_contacts']:,} sub-contacts" in out
    assert f"{size['cells']:,} cells" in out and "valid" in out and "nothing was built or run" in out


def test_check_estimates_time_from_the_counts_and_the_drive():
    """A step's cost is linear in the model's counts, each item adding a
    positive cost of its own (the measured costs: docs/speed.md); the
    steps are bounded by the drive, worked out by hand."""
    scene = build_scene(WILLIS)
    size = model_size(scene.geometry, scene.physics, scene.discretization, scene.loading)
    per_step = check.step_seconds(scene, size)
    for item in ("sub_contacts", "cells", "nodes"):
        once, twice = (check.step_seconds(scene, dict(size, **{item: size[item] + k * 1000})) for k in (1, 2))
        assert once > per_step and twice - once == pytest.approx(once - per_step, rel=1e-12), item
    d = scene.loading.drive
    drive, pre = check.step_bound(scene)
    # the Willis scene: a 1 mm limit at 7.5e-8 m a step after a ramp of 1000 steps
    assert (d.max_displacement, d.rate, d.ramp_steps) == (1e-3, 7.5e-8, 1000)
    assert drive == 1000 + 13334 and pre == 0
    longer = build_scene(WILLIS, ["loading.bending.max_displacement=2 mm", "loading.precompression.pressure=0.1 MPa"])
    assert check.step_bound(longer) == (1000 + 26667, longer.loading.precompression.max_steps)


def test_check_refuses_a_bad_scene_with_exit_2():
    r = _cli("check", WILLIS, "--set", "materials.units.E=15")
    assert r.returncode == 2 and "materials.units.E" in r.stderr and "did you mean 15 GPa?" in r.stderr


# --- predict: synthetic runs with known equations ---------------------------------
JOINT = dict(intercept=0.2, f_tj=4.5, sigma_v=2.5)       # MPa
BRICK = dict(intercept=0.5, f_tu=0.5)
# the synthetic runs' terms, inputs' columns and SI units
TERMS = ("f_tu", "f_tj", "f_tu^2", "f_tj^2", "sigma_v")
COLUMNS = dict(f_tu="f_tu_mpa", f_tj="f_tj_mpa", sigma_v="sigma_v_mpa")
UNITS = dict(f_tu="Pa", f_tj="Pa", sigma_v="Pa")


def _synthetic(n=60, seed=1):
    """n samples x 3 levels; each run fails in the mode of the lower known
    equation, with a 2 % multiplicative scatter."""
    rng = np.random.default_rng(seed)
    f_tu, f_tj = rng.uniform(2.0, 6.0, n), rng.uniform(0.1, 0.8, n)
    rows = []
    for i in range(n):
        for sv in (0.0, 0.25, 0.5):
            j = JOINT["intercept"] + JOINT["f_tj"] * f_tj[i] + JOINT["sigma_v"] * sv
            b = BRICK["intercept"] + BRICK["f_tu"] * f_tu[i]
            rows.append(dict(sample=i, f_tu_mpa=f_tu[i], f_tj_mpa=f_tj[i], sigma_v_mpa=sv,
                             failure_mode="joint" if j <= b else "brick",
                             strength_mpa=min(j, b) * (1 + 0.02 * rng.standard_normal())))
    return pd.DataFrame(rows)


@pytest.fixture(scope="module")
def predictor():
    ns = _synthetic()
    fits, _, _ = equations.prediction_equations(ns, TERMS, COLUMNS)
    return predict.build(fits, ns, build_scene(WILLIS), "synthetic runs", COLUMNS, UNITS, "synthetic")


def test_predict_recovers_the_known_equations_and_the_load(predictor):
    f_tu, f_tj, sv = 5.0, 0.3, 0.2
    p = predict.predict(predictor, f_tu="5 MPa", f_tj="300 kPa", sigma_v="0.2 N/mm^2")
    joint = JOINT["intercept"] + JOINT["f_tj"] * f_tj + JOINT["sigma_v"] * sv     # 1.85: the lower
    assert p.mode == "joint" and p.strength_mpa == pytest.approx(joint, rel=0.02)
    assert p.by_mode["brick"] == pytest.approx(BRICK["intercept"] + BRICK["f_tu"] * f_tu, rel=0.02)
    # P from sigma = 6 M / (b h^2), M = P a / 2 with the Willis wallette's b = 0.44, h = 0.114, a = 0.275 m
    assert p.load_kN == pytest.approx(p.strength_mpa * 1e6 * 0.44 * 0.114 ** 2 / 6 / (0.275 / 2) / 1e3, rel=1e-9)
    lo, hi = p.interval_mpa
    assert lo < p.strength_mpa < hi
    # the interval is that of a 2 % scatter: about +-4 % (1.96 sigma), not more than twice that
    assert 0.02 < (hi - lo) / p.strength_mpa < 0.16


def test_predict_names_the_brick_mode_where_its_equation_is_lower(predictor):
    p = predict.predict(predictor, f_tu=2.5e6, f_tj=0.7e6, sigma_v=0.5e6)
    assert p.mode == "brick" and p.strength_mpa == pytest.approx(0.5 + 0.5 * 2.5, rel=0.02)


@pytest.mark.parametrize("args,option,words", [
    (("3.5", "0.25 MPa", "0 MPa"), "f_tu", "has no unit, and f_tu is a quantity: did you mean '3.5 MPa'?"),
    (("3.5 MPa", "0.95 MPa", "0 MPa"), "f_tj", "fitted on"),
    (("3.5 MPa", "0.25 MPa", "1 MPa"), "sigma_v", "fitted on"),
    (("3.5 MPa", "0.25 mm", "0 MPa"), "f_tj", "a length"),
])
def test_predict_refuses_inputs_outside_the_fitted_range(predictor, args, option, words):
    with pytest.raises(InputError) as e:
        predict.predict(predictor, None, **dict(zip(("f_tu", "f_tj", "sigma_v"), args)))
    assert e.value.field == option and words in e.value.reason
    assert "230 x 65 x 114 mm" in e.value.reason or "length" in words or "no unit" in words


def test_predict_shows_a_lab_fitted_inputs_lab_value_beside_the_models():
    """f_tj fitted to a lab's bond-wrench results with the factor 2/3: the
    printout gives the model's 0.3 MPa and the lab's 0.45 MPa beside it; a
    lab value typed where the model's is asked for (0.9 MPa, outside the
    fitted 0.1 to 0.8) is refused with the conversion, 0.9 x 2/3 = 0.6."""
    ns = _synthetic()
    fits, _, _ = equations.prediction_equations(ns, TERMS, COLUMNS)
    record = {"f_tj": {"conversion": {"factor": 2 / 3, "source": "EN 1992-1-1:2004, 3.1.8(1), by analogy"},
                       "lab": {"quantity": "flexural bond strength"}}}
    p = predict.build(fits, ns, build_scene(WILLIS), "synthetic runs", COLUMNS, UNITS, "synthetic",
                      labs=predict.lab_conversions(record))
    lines = predict.predict(p, f_tu="5 MPa", f_tj="0.3 MPa", sigma_v="0.2 MPa").lines()
    assert ("f_tj 0.3 MPa (the lab's flexural bond strength 0.45 MPa x 0.6667: EN 1992-1-1:2004)"
            in lines[2]) and "f_tu 5 MPa," in lines[2]
    with pytest.raises(InputError) as e:
        predict.predict(p, f_tu="5 MPa", f_tj="0.9 MPa", sigma_v="0.2 MPa")
    assert ("f_tj is the model's value, 0.6667 x the lab's flexural bond strength (EN 1992-1-1:2004): a lab value "
            "of 0.9 MPa is f_tj = 0.6 MPa") in e.value.reason


def test_predict_on_the_command_line(tmp_path, predictor):
    path = tmp_path / "predictor.json"
    path.write_text(json.dumps(predictor))
    r = _cli("predict", str(path), "f_tu=5 MPa", "f_tj=0.3 MPa", "sigma_v=0.2 MPa")
    assert r.returncode == 0, r.stderr
    assert "governing: joint failure" in r.stdout and "95 % prediction interval" in r.stdout
    r = _cli("predict", str(path), "f_tu=5", "f_tj=0.3 MPa", "sigma_v=0.2 MPa")
    assert r.returncode == 2 and "did you mean '5 MPa'?" in r.stderr
    r = _cli("predict", str(tmp_path / "none.json"), "f_tu=5 MPa", "f_tj=0.3 MPa", "sigma_v=0")
    assert r.returncode == 2 and "predictor" in r.stderr


def test_predict_refuses_a_missing_or_unknown_input(predictor):
    with pytest.raises(InputError) as e:
        predict.predict(predictor, f_tu="3.5 MPa", f_tj="0.25 MPa")
    assert e.value.field == "sigma_v" and "missing" in e.value.reason
    with pytest.raises(InputError) as e:
        predict.predict(predictor, f_tu="3.5 MPa", f_tj="0.25 MPa", sigma_v=0, t="10 mm")
    assert e.value.field == "t" and "no input 't'" in e.value.reason


def test_predict_any_inputs_and_terms(tmp_path):
    """Equations over other inputs and terms (a study file's regression:
    a length in mm, a product term): the predictor takes each input in its
    unit and evaluates the terms as fitted."""
    rng = np.random.default_rng(3)
    n = 40
    t_mm, f_tj = rng.uniform(8.0, 14.0, n), rng.uniform(0.1, 0.8, n)
    rows = [dict(sample=i, t_mm=t_mm[i], f_tj_mpa=f_tj[i], sigma_v_mpa=sv, failure_mode="joint",
                 strength_mpa=0.1 + 0.02 * t_mm[i] + 6.0 * f_tj[i] * sv + 3.0 * f_tj[i])
            for i in range(n) for sv in (0.1, 0.3, 0.5)]
    ns = pd.DataFrame(rows)
    terms, columns = ("t", "f_tj", "f_tj*sigma_v"), dict(t="t_mm", f_tj="f_tj_mpa", sigma_v="sigma_v_mpa")
    fits, _, _ = equations.prediction_equations(ns, terms, columns)
    eq = fits["joint"][0]
    assert eq["coef"]["f_tj*sigma_v"] == pytest.approx(6.0, rel=0.02) and eq["coef"]["t"] == pytest.approx(0.02, rel=0.05)
    p = predict.build(fits, ns, build_scene(WILLIS), "synthetic", columns, dict(t="m", f_tj="Pa", sigma_v="Pa"),
                      "synthetic")
    assert p["inputs"]["t"] == dict(unit="m", shown="mm", column="t_mm")
    got = predict.predict(p, t="12 mm", f_tj="0.5 MPa", sigma_v="0.2 MPa")
    assert got.strength_mpa == pytest.approx(0.1 + 0.24 + 0.6 + 1.5, rel=0.01)
    assert got.inputs == dict(t=12.0, f_tj=0.5, sigma_v=0.2)
    with pytest.raises(InputError) as e:
        predict.predict(p, t=12, f_tj="0.5 MPa", sigma_v="0.2 MPa")
    assert e.value.field == "t" and "did you mean 12 mm?" in e.value.reason
    path = tmp_path / "predictor.json"
    path.write_text(json.dumps(p))
    r = _cli("predict", str(path), "t=12 mm", "f_tj=0.5 MPa", "sigma_v=0.2 MPa")
    assert r.returncode == 0, r.stderr
    assert "t 12 mm, f_tj 0.5 MPa, sigma_v 0.2 MPa" in r.stdout
    r = _cli("predict", str(path), "t=12", "f_tj=0.5 MPa", "sigma_v=0.2 MPa")
    assert r.returncode == 2 and "t: '12' has no unit" in r.stderr and "did you mean '12 mm'?" in r.stderr


def test_predict_builds_the_wallette_of_the_brick_it_is_given():
    """Equations with the brick's size as inputs (the geometry study): the
    load is that of the wallette of the given brick, its section the wall
    as built (6 H + 5 t), its thickness W and its shear span 1.1458 (L + t)
    (config/scenes/geometry.yaml); a scene that gives its section and
    absolute spans keeps them."""
    geometry = "config/scenes/geometry.yaml"
    p = {"inputs": {"L": dict(unit="m", shown="mm", setting="geometry.unit.length"),
                    "H": dict(unit="m", shown="mm", setting="geometry.unit.height"),
                    "W": dict(unit="m", shown="mm", setting="geometry.unit.width"),
                    "t": dict(unit="m", shown="mm", setting="geometry.joint_thickness"),
                    "f_tj": dict(unit="Pa", shown="MPa", setting="materials.joints.ft")}}
    x = dict(L=215.0, H=65.0, W=102.5, t=10.0, f_tj=0.3)        # the UK brick
    for scene, b, a in ((geometry, 6 * 0.065 + 5 * 0.010, 275 / 240 * 0.225), (WILLIS, 0.44, 0.275)):
        p["wallette"] = predict.build({}, pd.DataFrame(), build_scene(scene), "s", {}, {}, "v", {})["wallette"]
        w = predict.wallette_at(p, x)
        assert w["section_height_m"] == pytest.approx(b, rel=1e-12) and w["shear_span_m"] == pytest.approx(a, rel=1e-12)
        assert w["thickness_m"] == pytest.approx(0.1025) and w["unit_mm"] == pytest.approx([215.0, 65.0, 102.5])
    # inputs that leave the brick alone leave the wallette as fitted
    assert predict.wallette_at({"inputs": {"f_tj": p["inputs"]["f_tj"]}, "wallette": p["wallette"]}, x) == p["wallette"]


def test_predict_s_interval_covers_95_percent_of_new_wallettes():
    """Runs whose strength is the joint law times exp(e), e normal with SD
    0.1 (a known error): the interval's quantiles of the simulated over
    predicted strength are those of exp(e), exp(-+1.96 x 0.1) = 0.822 and
    1.217, within 3 standard errors of an order statistic of 4000 runs
    (0.013 on the ratio; the 5 % quantile, 0.848, is 0.026 off); and the
    interval predict gives holds 95 % of 4000 new wallettes drawn the same
    way, within binomial limits (3 standard deviations of the fraction of
    4000, and of the 4000 runs' quantiles: 0.95 +- 0.015)."""
    rng = np.random.default_rng(8)
    n, sd = 1334, 0.1

    def law(f_tj, sv):
        return JOINT["intercept"] + JOINT["f_tj"] * f_tj + JOINT["sigma_v"] * sv

    f_tj = rng.uniform(0.1, 0.8, n)
    rows = [dict(sample=i, f_tu_mpa=5.0, f_tj_mpa=f_tj[i], sigma_v_mpa=sv, failure_mode="joint",
                 strength_mpa=law(f_tj[i], sv) * np.exp(sd * rng.standard_normal()))
            for i in range(n) for sv in (0.0, 0.25, 0.5)]
    ns = pd.DataFrame(rows)
    fits, _, _ = equations.prediction_equations(ns, TERMS, COLUMNS)
    p = predict.build(fits, ns, build_scene(WILLIS), "synthetic", COLUMNS, UNITS, "synthetic")
    q = p["modes"]["joint"]
    assert q["ratio_q025"] == pytest.approx(np.exp(-1.959964 * sd), abs=0.013)
    assert q["ratio_q975"] == pytest.approx(np.exp(1.959964 * sd), abs=0.013 * 1.22)
    m = 4000
    new_tj, new_sv = rng.uniform(0.12, 0.78, m), rng.choice([0.0, 0.25, 0.5], m)
    y = law(new_tj, new_sv) * np.exp(sd * rng.standard_normal(m))
    inside = 0
    for tj, sv, yy in zip(new_tj, new_sv, y):
        lo, hi = predict.predict(p, f_tu=5e6, f_tj=tj * 1e6, sigma_v=sv * 1e6).interval_mpa
        inside += lo <= yy <= hi
    assert inside / m == pytest.approx(0.95, abs=0.015)


def test_predict_s_interval_is_that_of_the_out_of_fold_errors():
    """The interval's quantiles are those of the simulated over the
    out-of-fold strengths (each run predicted by an equation fitted without
    its sample: the error on a wallette the fit has not seen), recomputed
    here by an independent refit per fold (scikit-learn's LassoCV,
    tests/test_regression.py); on 10 samples with 2 % noise they are wider
    than those of the fitted strengths."""
    from sklearn.model_selection import GroupKFold
    from test_regression import _lasso_cv_predict
    rng = np.random.default_rng(11)
    f_tj = rng.uniform(0.1, 0.8, 10)
    ns = pd.DataFrame([dict(sample=i, f_tu_mpa=5.0, f_tj_mpa=f_tj[i], sigma_v_mpa=sv, failure_mode="joint",
                            strength_mpa=(JOINT["intercept"] + JOINT["f_tj"] * f_tj[i] + JOINT["sigma_v"] * sv)
                            * (1 + 0.02 * rng.standard_normal())) for i in range(10) for sv in (0.0, 0.25, 0.5)])
    fits, _, _ = equations.prediction_equations(ns, TERMS, COLUMNS)
    p = predict.build(fits, ns, build_scene(WILLIS), "synthetic", COLUMNS, UNITS, "synthetic")
    X = equations.features(equations.inputs_of(ns, COLUMNS), TERMS)
    y, groups = ns.strength_mpa.to_numpy(), ns["sample"].to_numpy()
    oof = np.empty_like(y)
    for train, test in GroupKFold(5).split(X, y, groups):
        oof[test] = _lasso_cv_predict(X[train], y[train], groups[train], X[test])
    q = p["modes"]["joint"]
    assert q["ratio_q025"] == pytest.approx(np.quantile(y / oof, 0.025), rel=1e-6)
    assert q["ratio_q975"] == pytest.approx(np.quantile(y / oof, 0.975), rel=1e-6)
    fitted = y / fits["joint"][0]["fitted"]
    assert q["ratio_q975"] - q["ratio_q025"] > np.quantile(fitted, 0.975) - np.quantile(fitted, 0.025)


# --- predict where either mode may govern: two noisy laws ------------------------
# a wallette's joint strength is the joint law times exp(SD_JOINT e), its brick
# strength the brick law times exp(SD_BRICK e'), e and e' independent standard
# normals; it fails in the lower of the two
SD_JOINT, SD_BRICK = 0.04, 0.12


def _joint_law(f_tj, sv):
    return JOINT["intercept"] + JOINT["f_tj"] * f_tj + JOINT["sigma_v"] * sv


def _brick_law(f_tu):
    return BRICK["intercept"] + BRICK["f_tu"] * f_tu


def _lower_of_two_noisy(rng, f_tu, f_tj, sv):
    """The strengths and failure modes of wallettes of the two noisy laws."""
    j = _joint_law(f_tj, sv) * np.exp(SD_JOINT * rng.standard_normal(sv.size))
    b = _brick_law(f_tu) * np.exp(SD_BRICK * rng.standard_normal(sv.size))
    return np.minimum(j, b), np.where(j <= b, "joint", "brick")


@pytest.fixture(scope="module")
def two_noisy_laws():
    """The predictor fitted on 1000 samples x 3 levels of the two noisy
    laws (about 1300 joint and 1700 brick runs), and those runs."""
    rng = np.random.default_rng(21)
    n = 1000
    f_tu, f_tj = np.repeat(rng.uniform(2.0, 6.0, n), 3), np.repeat(rng.uniform(0.1, 0.8, n), 3)
    sv = np.tile([0.0, 0.25, 0.5], n)
    y, mode = _lower_of_two_noisy(rng, f_tu, f_tj, sv)
    ns = pd.DataFrame(dict(sample=np.repeat(np.arange(n), 3), f_tu_mpa=f_tu, f_tj_mpa=f_tj, sigma_v_mpa=sv,
                           failure_mode=mode, strength_mpa=y))
    fits, _, _ = equations.prediction_equations(ns, TERMS, COLUMNS)
    return predict.build(fits, ns, build_scene(WILLIS), "synthetic", COLUMNS, UNITS, "synthetic"), ns


def _new_wallettes(p, seed, m, low, high):
    """m new wallettes of the two noisy laws, inside the fitted range, whose
    joint law over brick law lies between ``low`` and ``high``: their joint
    and brick laws, strengths, and predict's intervals and modes."""
    rng = np.random.default_rng(seed)
    f_tu, f_tj = rng.uniform(2.05, 5.95, 40 * m), rng.uniform(0.12, 0.78, 40 * m)
    sv = rng.choice([0.0, 0.25, 0.5], 40 * m)
    r = _joint_law(f_tj, sv) / _brick_law(f_tu)
    keep = np.flatnonzero((low < r) & (r < high))[:m]
    assert keep.size == m
    f_tu, f_tj, sv = f_tu[keep], f_tj[keep], sv[keep]
    y, _ = _lower_of_two_noisy(rng, f_tu, f_tj, sv)
    got = [predict.predict(p, f_tu=a * 1e6, f_tj=b * 1e6, sigma_v=c * 1e6) for a, b, c in zip(f_tu, f_tj, sv)]
    lo, hi = np.array([g.interval_mpa for g in got]).T
    return _joint_law(f_tj, sv), _brick_law(f_tu), y, lo, hi, np.array([g.mode for g in got])


def test_predict_s_interval_covers_95_percent_where_the_brick_mode_governs(two_noisy_laws):
    """Runs of two known laws with known errors (joint: SD 0.04 of its log,
    brick: 0.12), each failing in the lower of its two strengths.  Where the
    brick law lies well below the joint one (joint over brick above 1.4: the
    brick's 97.5 % strength, exp(1.96 x 0.12) B = 1.265 B, is below the
    joint's 2.5 %, exp(-1.96 x 0.04) J = 0.924 J) the brick mode governs,
    and the interval is that of the brick's error alone: exp(-+1.96 x 0.12)
    times the strength, 0.475 of it wide, within 10 % (the joint's error,
    a third of the brick's, gives 0.157); it holds 95 % of 3000 new
    wallettes, within 3 standard deviations of the fraction of 3000 and of
    the two quantiles of the brick runs' ratios (sqrt(2 x 0.025 x 0.975 /
    n) for n runs), and 0.01 more: the brick runs' ratios lack a little of
    their upper tail, a brick run that would have been strong near the
    crossing having failed in its joints instead."""
    p, ns = two_noisy_laws
    J, B, y, lo, hi, mode = _new_wallettes(p, 22, 3000, 1.4, np.inf)
    assert set(mode) == {"brick"}
    width = np.exp(1.96 * SD_BRICK) - np.exp(-1.96 * SD_BRICK)
    assert np.median((hi - lo) / np.minimum(J, B)) == pytest.approx(width, rel=0.10)
    n_brick = int((ns.failure_mode == "brick").sum())
    limit = 3 * np.sqrt(0.95 * 0.05 / y.size + 2 * 0.025 * 0.975 / n_brick) + 0.01
    assert np.mean((lo <= y) & (y <= hi)) == pytest.approx(0.95, abs=limit)


def test_predict_s_interval_at_the_crossing_of_the_two_equations(two_noisy_laws):
    """New wallettes of the two noisy laws (above) whose laws are within 8 %
    of each other, where either mode may fail whichever equation is the
    lower.  Their strength y = min(y_joint, y_brick) is at most either, so
    it exceeds top = min(exp(1.96 x 0.04) J, exp(1.96 x 0.12) B), the lower
    of the two modes' 97.5 % strengths, with a chance of at most 2.5 %; and
    it falls below bot = min(exp(-1.96 x 0.04) J, exp(-1.96 x 0.12) B) with
    a chance of at least 2.5 % (the weaker mode's alone) and at most 5 %
    (one or the other below its own).  Over 3000 such wallettes, at most
    2.5 % lie above the interval and 5 % below, each within 3 standard
    deviations of the fraction of 3000.  Whichever equation governs: the
    interval's upper bound is top within 3 %, and its lower bound reaches
    down to bot, 3 % allowed (a bound above bot misses more than 2.5 %
    below; the medians of their ratios: each mode's equation, fitted on its
    own runs, which near the crossing are the weaker ones, lies a few per
    cent below its law there); and the interval holds at least 92.5 % of
    its wallettes, less 3 standard deviations of the fraction of their
    number and of the two quantiles of the brick runs' ratios.  The governing mode's interval alone misses both: where
    the joint mode governs, its lower bound is the joint's, about 8 % above
    bot (the wallette may fail in its bricks, with their larger scatter),
    and where the brick mode governs, its upper bound the brick's, about
    7 % above top."""
    p, ns = two_noisy_laws
    J, B, y, lo, hi, mode = _new_wallettes(p, 23, 3000, 1 / 1.08, 1.08)
    top = np.minimum(np.exp(1.96 * SD_JOINT) * J, np.exp(1.96 * SD_BRICK) * B)
    bot = np.minimum(np.exp(-1.96 * SD_JOINT) * J, np.exp(-1.96 * SD_BRICK) * B)
    m = y.size
    assert np.mean(y > hi) <= 0.025 + 3 * np.sqrt(0.025 * 0.975 / m)
    assert np.mean(y < lo) <= 0.05 + 3 * np.sqrt(0.05 * 0.95 / m)
    n_brick = int((ns.failure_mode == "brick").sum())
    for governing in ("joint", "brick"):
        sel = mode == governing
        assert sel.sum() >= 300, governing
        assert np.median(hi[sel] / top[sel]) == pytest.approx(1.0, abs=0.03), governing
        assert np.median(lo[sel] / bot[sel]) <= 1.03, governing
        inside = np.mean(((lo <= y) & (y <= hi))[sel])
        assert inside >= 0.925 - 3 * np.sqrt(0.925 * 0.075 / sel.sum() + 2 * 0.025 * 0.975 / n_brick), governing


def test_check_takes_a_study_file_and_refuses_its_mistakes_with_exit_2(tmp_path):
    """`masonrydem check STUDY.yaml`: the Willis study described (its runs
    counted: 100 x 2 x 5 = 1,000), nothing drawn or run; a study file with
    a standard deviation without its unit is refused with exit 2, no
    traceback, the key as the file writes it and the unit of its mean in
    the suggestion; a scene's misspelled key names the nearest setting."""
    r = _cli("check", "config/studies/willis.yaml")
    assert r.returncode == 0, r.stderr
    assert "study 'willis': valid" in r.stdout and "= 1,000" in r.stdout and "nothing was drawn or run" in r.stdout
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: bad\nscene: config/scenes/willis.yaml\nsamples: 20\nseed: 1\n"
                   "variables:\n  bond: {setting: materials.joints.ft, distribution: lognormal, mean: 0.35 N/mm2, "
                   "sd: 0.1}\nvariants:\n  v: {draw: wallette}\n"
                   "sweep: {setting: loading.precompression.pressure, levels: [0 MPa]}\n")
    r = _cli("check", str(bad))
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "study.variables.bond.sd: 0.1 has no unit" in r.stderr and "did you mean '0.1 N/mm2'?" in r.stderr
    r = _cli("check", WILLIS, "--set", "materials.units.nuu=0.2")
    assert r.returncode == 2 and "materials.units.nuu: is not a setting here: did you mean 'nu'?" in r.stderr


def test_predict_says_what_it_answers_and_warns_where_a_modes_equation_is_missing(tmp_path):
    """Only the joint equation fitted (too few brick failures), the runs at
    0.5 MPa half brick failures: the answer names what it is (one
    wallette's strength by the study's equations, not a mean or a
    characteristic value) and warns that the brick mode has no equation,
    with the share of brick failures at the nearest level."""
    ns = _synthetic(n=30, seed=2)
    joint = ns[ns.failure_mode == "joint"]
    fits, rows, _ = equations.prediction_equations(joint, TERMS, COLUMNS)
    runs = pd.concat([joint, joint[joint.sigma_v_mpa == 0.5].assign(failure_mode="brick")])
    p = predict.build(fits, runs, build_scene(WILLIS), "synthetic", COLUMNS, UNITS, "synthetic", study="demo",
                      level="sigma_v", skipped={"brick": "too few runs to fit (3 samples)"})
    got = predict.predict(p, f_tu="4 MPa", f_tj="0.3 MPa", sigma_v="0.45 MPa")
    text = "\n".join(got.lines())
    assert "not a mean strength and not a characteristic (5 %) value" in text and "the study 'demo'" in text
    assert got.warnings == ("no brick-failure equation (too few runs to fit (3 samples)): the answer is the joint "
                            "equation's, too high wherever the brick mode governs; 50% of the study's runs at "
                            "sigma_v = 0.5 MPa failed in the brick mode",)
    assert "WARNING: no brick-failure equation" in text


def test_predict_refuses_another_wallette():
    """A scene other than the one fitted (the UK brick, 215 x 102.5 x 65
    mm) is refused, pointing to the geometry study's predictor; the
    fitted one is taken."""
    ns = _synthetic()
    fits, _, _ = equations.prediction_equations(ns, TERMS, COLUMNS)
    p = predict.build(fits, ns, build_scene(WILLIS), "synthetic", COLUMNS, UNITS, "synthetic")
    x = dict(f_tu="4 MPa", f_tj="0.3 MPa", sigma_v="0.2 MPa")
    uk = build_scene(WILLIS, ["geometry.unit.length=215 mm", "geometry.unit.width=102.5 mm"])
    with pytest.raises(InputError) as e:
        predict.predict(p, None, uk, **x)
    assert e.value.field == "--scene" and "215 x 65 x 102.5 mm" in e.value.reason
    assert "results/studies/geometry/study/predictor.json" in e.value.reason
    assert predict.predict(p, None, build_scene(WILLIS), **x).mode == "joint"


@pytest.mark.parametrize("samples", [7, 12, 80])
def test_check_says_what_a_study_s_sample_count_will_give(tmp_path, samples):
    """`check` on the Waal study at 7, 12 and 80 samples says, before
    anything runs, what its analysis can give: a mode's equation needs 7
    samples failing in it (the nested 5-fold cross-validation over whole
    samples); Sobol indices need 10 runs of a variant and level; the
    non-parametric 5 % fractile's 95 % interval has a lower end, X_(1),
    only where P(no run below the fractile) = 0.95^n <= 0.025, n >= 72
    (computed here from the binomial, not the package)."""
    import math
    import yaml
    study = yaml.safe_load(open("config/studies/waal.yaml"))
    study.update(samples=samples, scene=str(__import__("pathlib").Path(study["scene"]).resolve()))
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(study))
    r = _cli("check", str(path))
    assert r.returncode == 0, r.stderr
    out = r.stdout
    need = math.ceil(math.log(0.025) / math.log(0.95))
    assert need == 72 and f"outputs at {samples} samples x 3 levels:" in out
    assert f"at least 7 of the {samples} samples fail in it" in out
    assert ("Sobol indices: none (7 runs per variant and level; a group needs 10" in out) == (samples < 10)
    assert (f"Sobol indices: {samples} runs per variant and level" in out) == (samples >= 10)
    assert (f"has no lower end ({samples} runs per variant and level; it needs {need})" in out) == (samples < need)
    assert ("non-parametric one's interval has both ends" in out) == (samples >= need)


def test_check_suggests_a_value_and_its_source_for_each_missing_material_property(tmp_path):
    """Each material property the scene schema requires, left out of the
    small study's scene: the scene is refused naming it, with a value and
    its source (the command line: exit 2, once); that value put back, the
    scene passes.  A value said to be the source paper's model is the
    Willis scene's (the scene of that model)."""
    import yaml
    from masonrydem.pipeline.check import SUGGESTED, explained
    from masonrydem.scene import SCHEMA, to_si
    mats = SCHEMA["properties"]["materials"]["properties"]
    required = {f"materials.{k}.{p}" for k in ("units", "joints") for p in mats[k]["required"]}
    assert required <= set(SUGGESTED)
    willis = yaml.safe_load(open(WILLIS))["materials"]
    for key in sorted(required):
        _, part, prop = key.split(".")
        raw = yaml.safe_load(open("config/scenes/solid.yaml"))
        del raw["materials"][part][prop]
        with pytest.raises(InputError) as e:
            build_scene(raw)
        value, source = SUGGESTED[key]
        assert str(explained(e.value)) == (f"{key}: missing: a scene gives every material property; where you "
                                           f"have no value of your own, {value} is {source}")
        raw["materials"][part][prop] = value if " " in value else float(value)
        build_scene(raw)
        if "the source paper's model" in source:
            unit = mats[part]["properties"][prop].get("unit", "")
            assert to_si(value, unit, key) == pytest.approx(willis[part][prop]), key
    del raw["materials"]["joints"]["ks_ratio"]
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(raw))
    r = _cli("check", str(tmp_path / "scene.yaml"))
    assert r.returncode == 2 and "materials.joints.ks_ratio: missing" in r.stderr and "0.4 is k_s = 0.4 k_n" in r.stderr


def test_predict_builds_the_vertical_wallette_of_the_brick_it_is_given():
    """A vertical-bending study's equations with the brick's size as
    inputs: the section is the bed joints' length as built and the shear
    span scales with the course height, as the scene itself builds them
    for that brick (config/scenes/solid_vertical.yaml with the UK brick)."""
    vertical = "config/scenes/solid_vertical.yaml"
    p = {"inputs": {k: dict(unit="m", shown="mm", setting=s) for k, s in (
        ("L", "geometry.unit.length"), ("H", "geometry.unit.height"), ("W", "geometry.unit.width"),
        ("t", "geometry.joint_thickness"))}}
    p["wallette"] = predict.build({}, pd.DataFrame(), build_scene(vertical), "s", {}, {}, "v", {})["wallette"]
    w = predict.wallette_at(p, dict(L=215.0, H=65.0, W=102.5, t=10.0))
    uk = build_scene(vertical, ["geometry.unit.length=0.215", "geometry.unit.height=0.065",
                                "geometry.unit.width=0.1025", "geometry.joint_thickness=0.010"]).loading.bending
    assert w["section_height_m"] == pytest.approx(uk.section, rel=1e-12) == pytest.approx(2 * 0.225 - 0.010)
    assert w["shear_span_m"] == pytest.approx(uk.shear_span, rel=1e-12) == pytest.approx(3 * 0.075)
