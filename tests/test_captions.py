"""The report's captions (report/captions.py) and the tables they read,
each from a tiny table whose numbers are known: every caption names the
numbers of its rows, and fills its template (workflow/report/) without a
field left over."""
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from masonrydem.analysis import accuracy, statistics as analysis, validation
from masonrydem.report import captions, figures, landing
from masonrydem.scene import build_scene
from masonrydem.study.sampling import sampling_check

REPORT = Path(__file__).parent.parent / "workflow" / "report"


def fill(name, values):
    """The template NAME filled with ``values``; a field missing raises."""
    text = (REPORT / f"{name}.rst").read_text().format(**values)
    assert "{" not in text
    return text


def test_write_captions_fills_each_template_with_its_values(tmp_path):
    (tmp_path / "a.rst").write_text("mean {m:.2f} kN")
    (tmp_path / "b.rst").write_text("no fields")
    out = [tmp_path / "out" / "a.rst", tmp_path / "out" / "b.rst"]
    captions.write_captions([tmp_path / "a.rst", tmp_path / "b.rst"], out, {"a": {"m": 1.234}})
    assert out[0].read_text() == "mean 1.23 kN" and out[1].read_text() == "no fields"


def test_validation_summary():
    table = pd.DataFrame(dict(case=["reference", "half_rate"], sigma_v_mpa=[0.0, 0.15], P_max_kN=[13.3141, 13.5],
                              disp_at_peak_mm=[0.1234, 0.2], strength_mpa=[0.5, 0.6],
                              initial_stiffness_kN_per_mm=[250.04, 240.0], failure_mode=["joint", "brick"],
                              status=["load_drop", "displacement_limit"], P_max_change_vs_reference_pct=[0.0, 1.234]))
    lines = fill("validation_summary", captions.validation_summary(table)).splitlines()[-2:]
    assert lines[0] == ("- reference, sigma_v = 0 MPa: **P_max 13.314 kN** at 0.123 mm (0.500 MPa, initial stiffness "
                        "250.0 kN/mm), joint failure, load_drop, +0.00 % against the reference")
    assert lines[1].startswith("- half_rate, sigma_v = 0.15 MPa: **P_max 13.500 kN**")
    assert lines[1].endswith("brick failure, displacement_limit, +1.23 % against the reference")


def test_hard_cases_count_the_runs_that_miss_their_mode():
    table = pd.DataFrame(dict(run=["x", "x_half_rate"], case=["x", "x"], status=["load_drop", "step_limit"],
                              ok=[True, False], P_max_kN=[10.0, 10.1], failure_mode=["brick", "joint"],
                              expect=["joint", "joint"], mode_as_expected=[False, True], steps=[1000, 2000],
                              ratio_at_peak=[0.3, 0.2], unbalance_at_peak=[0.01234, 0.002],
                              post_peak=["quasi-static", "dynamic"],
                              half_rate_change_pct=[np.nan, 1.0]))
    values = captions.hard_cases(table, 0.01)
    assert (values["n"], values["unmet"]) == (2, 2)
    text = fill("hard_cases", values)
    assert "2 of 2 runs miss their expected mode" in text and "near equilibrium,\nbelow 0.01)" in text
    assert ("- x: load_drop, **P_max 10.000 kN**, brick failure (expected: joint, NOT MET), 1000 steps, "
            "load unbalanced by 0.0123 at the peak, post-peak quasi-static\n") in text
    assert "- x_half_rate: step_limit," in text and "post-peak dynamic, +1.00 % against x" in text


def test_reduced_models_against_the_full_one():
    table = pd.DataFrame(dict(case=["c1", "c1"], model=["full", "rigid"], sigma_v_mpa=[0.15, 0.15],
                              f_tj_mpa=[0.3, 0.3], P_max_kN=[10.0, 10.1], change_pct=[0.0, 1.0],
                              failure_mode=["joint", "joint"], wall_time_s=[20.0, 2.0], speedup=[1.0, 10.0],
                              good_enough=[True, True]))
    values = captions.reduced(table, 0.02)
    assert values["tolerance"] == "2 %" and values["good"] == "rigid on c1"
    assert values["lines"] == ("- c1 (sigma_v 0.15 MPa, f_tj 0.3 MPa): full 10.000 kN (joint, 20.0 s); "
                               "rigid 10.100 kN (+1.0 %, joint, 10.0 x faster, good enough)")
    fill("reduced", values)
    assert captions.reduced(table.assign(good_enough=False), 0.02)["good"] == "none"


def test_specimens_triplet_against_its_closed_forms():
    table = pd.DataFrame(dict(case=["tension", "triplet_sv02"], test=["tension", "triplet"], sigma_v_mpa=[0.0, 0.2],
                              f_tj_mpa=[0.3, 0.3], P_max_kN=[5.0, 20.0], disp_at_peak_mm=[0.01, 0.05],
                              stress_mpa=[0.2, 0.4], failure_mode=["joint", "joint"], status=["load_drop"] * 2,
                              peak_closed_form_mpa=[np.nan, 0.42], peak_error=[np.nan, -0.0476],
                              end_stress_mpa=[0.0, 0.15], residual_closed_form_mpa=[np.nan, 0.1456],
                              residual_error=[np.nan, 0.03]))
    first, second = fill("specimens", captions.specimens(table)).splitlines()[-2:]
    assert first == ("- tension (tension, sigma_v 0 MPa, f_tj 0.3 MPa): P_max 5.00 kN at 0.010 mm, stress 0.200 MPa, "
                     "joint failure, load_drop")
    assert second.endswith("; peak against c + sigma tan phi = 0.420 MPa: -4.8 %; at the end 0.150 MPa against "
                           "sigma tan phi = 0.146 MPa: +3.0 %")


def test_sampling_check_table_and_caption(willis):
    """A sample of four rows with known means and COVs; the caption's
    E_b-f_tu correlation, the largest other one (off the diagonal) and the
    largest relative deviations from the targets."""
    v = {x.name: x for x in willis.variables}
    sample = pd.DataFrame({n: v[n].mean * np.array([0.9, 1.0, 1.0, 1.1]) for n in v})
    sample["f_tj"] = v["f_tj"].mean * np.array([1.0, 1.0, 1.1, 1.1])     # mean +5 %
    achieved = np.eye(4)
    names = list(v)
    i, j, k = names.index("E_b"), names.index("f_tu"), names.index("phi_j")
    achieved[i, j] = achieved[j, i] = 0.49
    achieved[i, k] = achieved[k, i] = -0.03
    check = sampling_check(sample, achieved, willis.variables)
    assert list(check.variable) == names and check.loc[i, f"corr_{names[j]}"] == 0.49
    cov = np.std([0.9, 1.0, 1.0, 1.1], ddof=1)
    assert check.set_index("variable").loc["E_b", "cov_sample"] == pytest.approx(cov)
    values = captions.sampling_check(check, achieved, willis.correlations)
    assert values["targets"] == "E_b-f_tu target 0.5, achieved **0.490**" and values["other"] == pytest.approx(0.03)
    assert values["mean_dev"] == pytest.approx(5.0)
    # the largest COV deviation: f_tj's, 1, 1, 1.1, 1.1 x its mean against its target 0.4
    assert values["cov_dev"] == pytest.approx(100 * (1 - np.std([1, 1, 1.1, 1.1], ddof=1) / 1.05 / 0.4))
    assert "**0.490**" in fill("sampling_check", values)
    # a study without a targeted correlation: every off-diagonal one is 'other'
    assert captions.sampling_check(check, achieved, {}) == dict(values, targets="none targeted", other=0.49)


def _runs():
    """One variant at two levels: three joint runs (P_max 9, 10, 11 kN at 0
    MPa, 14, 15, 16 at 0.5 MPa), one brick run and one failed run at each."""
    rows = []
    for sv, base in ((0.0, 10.0), (0.5, 15.0)):
        for i, (p, mode) in enumerate([(base - 1, "joint"), (base, "joint"), (base + 1, "joint"), (2 * base, "brick")]):
            rows.append(dict(variant="nonspatial", sigma_v_mpa=sv, sample=i, P_max_kN=p, strength_mpa=p / 10,
                             failure_mode=mode, ok=True, status="load_drop", f_tj_mpa=0.1 * p,
                             f_tu_mpa=4.0 - 0.01 * p * (1 + i % 2), phi_j_deg=35.0 + i, E_b_mpa=15000.0 + i,
                             drop_after_peak=0.1 * (i + 1)))
        rows.append(dict(variant="nonspatial", sigma_v_mpa=sv, sample=4, P_max_kN=np.nan, strength_mpa=np.nan,
                         failure_mode="none", ok=False, status="step_limit", f_tj_mpa=0.3, f_tu_mpa=3.75,
                         phi_j_deg=35.0, E_b_mpa=15000.0, drop_after_peak=np.nan))
    return pd.DataFrame(rows)


SPEC = dict(study="demo", scene="demo_scene", test="four-point out-of-plane horizontal bending", precompression=True,
              wallette="6 courses of 4 units of 230 x 65 x 114 mm in running bond with 10 mm joints",
            variants={"nonspatial": "one draw of the properties for the whole wallette"},
            draws={"nonspatial": "wallette"}, inputs=["f_tj", "f_tu", "phi_j", "E_b"],
            categories=[["Study", "the statistics"], ["Prediction", "the equations"], ["3-D pictures", "states"]])


def test_statistics_captions(level, inputs):
    """All modes at 0 MPa: mean (9 + 10 + 11 + 20) / 4 = 12.5 kN, a quarter
    brick failures; two failed runs excluded; the increase of the joint
    mean from 10 to 15 kN is +50 %."""
    runs = _runs()
    st, corr, inc = analysis.study_tables(runs, 200, 0, inputs, level)
    values = captions.statistics(runs, st, corr, inc, level, inputs, SPEC)
    source = landing.source(None, "config/studies/demo.yaml")
    page = landing.landing(runs, st, int((~runs.ok).sum()), level, SPEC, source)
    landing_text = (REPORT / "workflow.rst").read_text().format(**page)
    assert "No source paper is compared" in landing_text
    # a study without a paper cites its study file, and no one else's source
    assert "**Source.** the study file ``config/studies/demo.yaml``." in landing_text and "Willis" not in landing_text
    assert landing_text.startswith("masonrydem: the demo study, a wallette in horizontal bending\n")
    assert "- Study_: the statistics.\n- Prediction_: the equations.\n- `3-D pictures`_: states." in landing_text
    assert "Accuracy_" not in landing_text and "spatial" not in landing_text.replace("nonspatial", "")
    assert "none" not in values["correlations"]["fields"] and values["correlations"]["fields"] == ""
    text = fill("statistics", values["statistics"])
    assert "**2 of 10 runs excluded** (step_limit: 2)" in text
    # the mean of resamples of 9, 10, 11, 20 lies between 9 and 20
    lo, hi = re.search(r"- nonspatial, 0 MPa: mean \*\*12.50 kN\*\* \(([\d.]+) to ([\d.]+); 1.250 MPa\)", text).groups()
    assert 9.0 <= float(lo) < 12.5 < float(hi) <= 20.0
    assert "25 % brick failures (" in text
    assert "nonspatial joint **+50 %** (" in values["increase"]["lines"]
    assert values["increase"]["lines"].endswith(" (from 0 to 0.5 MPa)")
    fill("increase", values["increase"])
    # four runs: the 5 % band of r is 1.96 / sqrt(3)
    assert values["correlations"]["noise"] == f"+-{1.96 / np.sqrt(3):.2f} for n = 4"
    assert values["correlations"]["spreads"].startswith("nonspatial: f_tj_mpa ")
    assert "- nonspatial, 0 MPa: f_tj_mpa (+1.00)" in fill("correlations", values["correlations"])


def test_study_figures_captions(level, inputs):
    runs = _runs()
    st = analysis.statistics(runs, level)
    corr = analysis.correlations(runs, inputs, level)
    sv = analysis.scatter_level(runs, level)
    assert sv == 0.0                                  # of 0 and 0.5, nearest 0.25 is the first
    values = captions.study_figures(runs, st, corr, sv, level, inputs, "nonspatial")
    assert values["brick_share"]["lines"] == "nonspatial: 0 MPa 25 %, 0.5 MPa 25 %"
    assert values["scatter_deviation"]["n"] == 4 and values["scatter_deviation"]["lines"].startswith("f_tj_mpa +1.00")
    # drop after the peak: joint runs 0.1, 0.2, 0.3 (median 20 %), the brick run 0.4
    assert "nonspatial 0 MPa joint 20 % (3 runs)" in values["curves_by_mode"]["lines"]
    assert "nonspatial 0.5 MPa brick 40 % (1 runs)" in values["curves_by_mode"]["lines"]
    # running mean at 0 MPa in sample order 9, 10, 11, 20: 9, 9.5, 10, 12.5
    se = np.std([9, 10, 11, 20], ddof=1) / 2 / 12.5
    # (the last 20 % of 4 runs: the running means 10 and 12.5 of the last two, 20 % apart)
    assert values["running_mean"]["lines"].startswith(f"nonspatial 0 MPa 20.0 % (standard error of the mean "
                                                      f"{100 * se:.1f} %)")
    for name, v in values.items():
        fill(name, v)


def test_study_pictures_pick_the_run_nearest_the_median_where_the_mode_is_most_frequent(level):
    runs = _runs()
    runs.loc[(runs.sigma_v_mpa == 0.5) & (runs["sample"] == 0), "failure_mode"] = "brick"
    pick, at = captions.typical_run(runs, "nonspatial", "joint", level)
    assert pick["sample"] == 1 and pick.sigma_v_mpa == 0.0 and len(at) == 3      # 3 joint runs at 0, 2 at 0.5
    bpick, bat = captions.typical_run(runs, "nonspatial", "brick", level)
    assert bpick.sigma_v_mpa == 0.5 and len(bat) == 2
    assert captions.typical_run(runs, "spatial", "joint", level) == (None, None)
    text = fill("study_pictures", captions.study_pictures([("nonspatial", "joint", pick, at),
                                                            ("spatial", "joint", None, None)], level))
    assert ("- nonspatial, joint failure: sample 1 at 0 MPa (the level with most joint failures, 3 of them, median "
            "P_max 10.00 kN): P_max **10.00 kN**, repeated exactly by the rerun\n"
            "- spatial, joint failure: no run") in text


def test_equations_caption():
    rows = [dict(mode="joint", n=40, alpha=0.001234, mape_pct=5.04, cv_mape_pct=6.0, equation="sigma = 0.1 + 1 f_tj"),
            dict(mode="brick", n=3, equation="too few runs to fit (3 samples, the nested 5-fold CV needs 7)"),
            dict(mode="lower of two", n=43, mape_pct=7.0, mode_agreement=0.93, equation="the joint equation alone")]
    text = fill("equations", captions.equations(rows, ("f_tj", "sigma_v"), "per_wall"))
    assert "terms f_tj, sigma_v," in " ".join(text.split()) and "runs of the variant per_wall" in text
    assert ("- joint failure (40 runs): **sigma = 0.1 + 1 f_tj**, MAPE **5.0 %** on the runs it was fitted to, "
            "**6.0 %** out of fold; alpha 0.00123") in text
    assert "- brick failure (3 runs): too few runs to fit" in text
    assert "- the predictor, the joint equation alone (43 runs): MAPE **7.0 %**, failure mode right in **93 %**" in text


def test_design_table_and_caption(willis, columns, monkeypatch):
    """One joint equation sigma = 0.1 + sigma_v (as the lower of two it
    stands for both): at the mean properties it is 0.1 + sigma_v; the
    caption reads the table at the simulated levels (0.25 MPa interpolated).
    The design rules read f_tj and f_tu of the wallette of mean properties:
    the Willis study's means, 0.3 and 3.75 MPa.  The figure's prediction
    names the equations fitted, is not drawn without one, and its axis is
    the study's level (p here)."""
    eq = dict(intercept=0.1, coef=dict(zip(willis.features, [0.0, 0.0, 0.0, 0.0, 1.0])))
    ns = pd.DataFrame(dict(sample=[0, 1, 0, 1], f_tu_mpa=[3.0, 4.0, 3.0, 4.0], f_tj_mpa=[0.2, 0.4, 0.2, 0.4],
                           sigma_v_mpa=[0.0, 0.0, 0.5, 0.5], strength_mpa=[0.1, 0.1, 0.6, 0.6]))
    mean_scene = build_scene(willis.scene, settings=willis.mean_settings())
    inputs = dict(validation.design_inputs(mean_scene), l_o=0.115, h_b=0.086, c_ratio=1.5)
    assert (inputs["ft_units"], inputs["ft_joints"]) == pytest.approx((3.75, 0.3), rel=1e-15)
    design = validation.design_table({"joint": (eq, ns.strength_mpa.to_numpy())}, ns, 0.0, np.array([0.0, 0.5]),
                                     inputs, willis.means(), columns, willis.sweep_name, "sigma_v_mpa")
    assert design.prediction.tolist() == pytest.approx([0.1, 0.6]) and design.band_sd.tolist() == [0.0, 0.0]
    # the band adds the residual scatter to the properties' (none here: the equation takes none of them)
    banded = validation.design_table({"joint": (eq, ns.strength_mpa.to_numpy())}, ns, 0.03, np.array([0.0, 0.5]),
                                     inputs, willis.means(), columns, willis.sweep_name, "sigma_v_mpa")
    assert banded.band_sd.tolist() == pytest.approx([0.03, 0.03], rel=1e-12) and banded.property_sd.max() == 0.0
    assert design.lg_stepped.iloc[0] == pytest.approx(1.5 * 0.3 * 0.115 / 0.086) and design.lg_brick.iloc[0] == 1.875
    simulated = pd.DataFrame({"mean": [0.35], "std": [0.05]}, index=pd.Index([0.25], name="sigma_v_mpa"))
    values = captions.design_comparison(design, simulated, ["joint"], 0.02, 2, inputs, "nonspatial")
    text = " ".join(fill("design_comparison", values).split())
    assert "the joint equation alone (too few runs of the other mode)" in text
    assert "l_o = 115 mm" in text and "h_b = 86 mm" in text
    assert ("- 0.25 MPa: simulated **0.350 +- 0.050 MPa**, predicted **0.350 +- 0.000 MPa** at the mean properties, "
            "**0.350 MPa** on average over the samples") in text
    assert captions.design_comparison(design, simulated, [], 0.02, 2, inputs, "nonspatial")["equations"] == \
        "no equation (too few runs)"
    saved = []
    monkeypatch.setattr(figures, "save", lambda fig, path: saved.append(fig))
    for fitted in (["joint", "brick"], ["joint"], []):
        figures.design_comparison(design, simulated, "x.png", "nonspatial", analysis.Level("p_mpa", "p", "MPa"), fitted)
    labels = [[t.get_text() for t in fig.axes[0].get_legend().get_texts()] for fig in saved]
    assert labels[0][0] == "prediction at mean properties (lower of the joint and brick equations)"
    assert labels[1][0].startswith("prediction at mean properties (joint equation alone: too few runs")
    assert not any(x.startswith("prediction") or "over the samples" in x for x in labels[2])
    assert all(fig.axes[0].get_xlabel() == "$p$ (MPa)" for fig in saved)


def _sweep():
    """Case a's path p1, p2, p4 (the two finest within 0.2 %, the three
    finest not monotone: reference 10.0 kN), a candidate c (+0.2 %, 2 s)
    and the defaults (+1 %); case b not converged; rate_x around the
    defaults, twice the time."""
    rows = [dict(case="a", setting=s, P_max_kN=p, failure_mode="joint", ok=True, status="load_drop", steps=100,
                 wall_time_s=t, blocks="elasto-plastic", cells=c, subcontact_refine=1, tets=1, subcontacts=1,
                 units=24)
            for s, p, t, c in (("p1", 9.9, 1.0, "1x1x1"), ("p2", 10.02, 5.0, "2x1x1"), ("p4", 10.0, 9.0, "4x1x1"),
                               ("c", 10.02, 2.0, "2x1x1"), ("default", 10.1, 3.0, "8x6x2"),
                               ("rate_x", 10.2, 6.0, "8x6x2"))]
    rows += [dict(r, case="b", P_max_kN=p) for r, p in zip(rows, (5.0, 4.0, 4.5, 4.2, 4.2, 4.2))]
    return accuracy.sweep_table(rows, ["a", "b"], ["p1", "p2", "p4"], ["c"], 0.01)


def test_accuracy_convergence_and_choice():
    table, conv = _sweep()
    assert accuracy.judged_cases(conv) == ["a"]
    assert table.set_index(["case", "setting"]).loc[("a", "rate_x"), "kind"] == "one-at-a-time"
    choice = accuracy.choose(table, conv, 0.02)
    # judged on case a: c (+0.2 %, 2 s) is the cheapest candidate within 2 %, the defaults (+1 %) beside it
    assert choice.loc[choice.knee, "setting"].tolist() == ["c"]
    assert choice.set_index("setting").loc["default", "max_abs_error"] == pytest.approx(0.01)
    conv_text = fill("accuracy_convergence", dict(captions.accuracy_convergence(conv), tolerance="1 %"))
    assert "- a: **10.000 kN** (joint failure), finest level (two finest within 0.20 %" in conv_text
    values = captions.accuracy_choice(table, conv, choice, {"rate_x": "default"}, 0.02, ["numerics.cells=[8, 6, 2]"])
    assert values["cases"] == "a; not judged, no converged reference: b"
    assert values["knee"] == "**c**, largest error 0.20 %, modes right, 2.0 s"
    assert values["default"] == "**default**, largest error 1.00 %, modes right, 3.0 s"
    assert values["oat"] == "- rate_x: a +0.99 % in 2.00 x the time; b +0.00 % in 2.00 x the time"
    assert "(config/config.yaml, ``numerics``: numerics.cells=[8, 6, 2])" in fill("accuracy_choice", values)


def test_accuracy_scaling_fits_and_caption():
    """Run time ~ units^2 and ~ cells^3, time per step ~ units: exponents
    recovered and named in the caption with the wallettes' courses."""
    units = pd.DataFrame(dict(units=[12, 24, 48], wall_time_s=[1.0, 4.0, 16.0], steps=[100, 200, 400],
                              tets=[10, 20, 40]))
    runs = pd.DataFrame(dict(case=["a"] * 3 + ["b"], setting=["c1", "c2", "c3", "c1"], ok=True, cells_n=[1, 2, 4, 1],
                             wall_time_s=[1.0, 8.0, 64.0, 1.0], steps=[10, 10, 10, 10], tets=[6, 48, 384, 6]))
    table = accuracy.scaling(units, runs, ["c1", "c2", "c3"])
    assert table.step_time_us.tolist()[:3] == pytest.approx([1e4, 2e4, 4e4])
    assert table.against.tolist() == ["units"] * 3 + ["cells"] * 3 and table["size"].tolist() == [12, 24, 48, 1, 2, 4]
    assert table.run_time_s.tolist() == [1.0, 4.0, 16.0, 1.0, 8.0, 64.0]
    values = captions.accuracy_scaling(table, [6, 12, 24])
    assert values["courses"] == "6, 12, 24"
    assert values["fits"] == ("run time ~ units^2.00; time per step ~ units^1.00; run time ~ cells^3.00; "
                              "time per step ~ cells^3.00")
    fill("accuracy_scaling", values)


def test_accuracy_subsample_caption_says_undefined_for_one_run():
    """Two samples at 0 MPa (P_max default 10, 12; fine 11, 12) and one
    excluded at 0.15 MPa, which leaves one run there: its COV undefined."""
    default = pd.DataFrame(dict(sigma_v_mpa=[0.0, 0.0, 0.15, 0.15], sample=[0, 1, 0, 1], ok=[True, True, True, False],
                                P_max_kN=[10.0, 12.0, 13.0, np.nan], failure_mode=["joint", "joint", "brick", "none"]))
    fine = default.assign(P_max_kN=[11.0, 12.0, 13.0, np.nan], ok=True)
    table = accuracy.compare_subsample(default, fine)
    values = captions.accuracy_subsample(table, ["numerics.cells=[8, 8, 4]"])
    assert values["n"] == 2 and values["levels"] == "0, 0.15" and values["fine"] == "numerics.cells=[8, 8, 4]"
    first, second = values["lines"].splitlines()
    assert first.startswith(f"- 0 MPa, 2 runs (0 excluded): mean P_max 11.000 kN default, 11.500 kN fine "
                            f"({100 * (11 / 11.5 - 1):+.1f} %)")
    assert second.startswith("- 0.15 MPa, 1 runs (1 excluded)") and "COV undefined default, undefined fine" in second
    assert "nan" not in fill("accuracy_subsample", values).lower()
    assert len(accuracy.paired(default, fine)) == 4


def test_the_study_figures_have_a_panel_per_variant_and_none_empty(monkeypatch, tmp_path, level, inputs):
    """One variant: the running mean, the correlations and the curves draw
    one panel each, every panel with its lines (no empty second panel);
    two variants, two."""
    saved = []
    monkeypatch.setattr(figures, "save", lambda fig, path: saved.append(fig))
    runs = _runs()
    for variants in (["nonspatial"], ["nonspatial", "other"]):
        both = pd.concat([runs.assign(variant=v) for v in variants], ignore_index=True)
        c = analysis.study_tables(both, 50, 0, inputs, level)[1]
        curves = pd.DataFrame([dict(variant=v, sigma_v_mpa=sv, sample=s, displacement_mm=u, load_kN=u)
                               for v in variants for sv in (0.0, 0.5) for s in range(4) for u in (0.0, 0.1)])
        saved.clear()
        figures.running_mean(both, tmp_path / "a.png", level)
        figures.correlation_vs_sigma(c, tmp_path / "b.png", level, inputs, {col: col for col in inputs})
        figures.curves_by_mode(both, curves, [0.0, 0.5], tmp_path / "c.png", level)
        running, correlation, by_mode = saved
        assert len(running.axes) == len(variants) and all(ax.lines for ax in running.axes)
        assert len(correlation.axes) == len(variants) and all(ax.lines for ax in correlation.axes)
        assert len(by_mode.axes) == 2 * len(variants) and all(ax.lines for ax in by_mode.axes)


def test_the_small_study_says_in_words_what_its_7_samples_cannot_give():
    """The committed 7-sample study (config/studies/small.yaml): no caption
    prints 'undefined' or 'nan'; the sensitivity caption gives the runs and
    why there are no indices; a missing brick equation is named with why;
    no page of a table has a column without a value."""
    report = Path("results/studies/small/report")
    texts = {p.name: " ".join(p.read_text().split()) for p in report.glob("*.rst")}
    assert len(texts) >= 14
    for name, text in texts.items():
        assert not re.search(r"\bundefined\b|\bnan\b", text, re.I), name
    assert "per_wall, 0 MPa: 7 runs, too few for a surrogate" in texts["sensitivity.rst"]
    assert "- brick failure (" in texts["equations.rst"] and "too few runs to fit" in texts["equations.rst"]
    for page in (report / "tables").glob("*.html"):
        for row in re.findall(r"<tr>(.*?)</tr>", page.read_text(), re.S):
            cells = re.findall(r"<td>(.*?)</td>", row, re.S)
            assert not cells or any(c.strip() for c in cells), page.name
