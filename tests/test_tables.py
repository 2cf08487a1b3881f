"""The result tables the report shows (validation.py), each on constructed
rows whose answers are computed by hand."""
import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from masonrydem.analysis.validation import hard_cases_table, initial_stiffness, reduced_table, specimen_table, summary_table


def _row(**kw):
    base = dict(sigma_v_mpa=0.0, P_max_kN=10.0, disp_at_peak_mm=0.5, strength_mpa=1.0, failure_mode="joint",
                status="load_drop", ok=True, steps=1000, peak_step=500, ratio_at_peak=1e-4, unbalance_at_peak=1e-3,
                post_peak="quasi-static", wall_time_s=2.0, classification="joint failure", message="",
                f_tj_mpa=0.3)
    return {**base, **kw}


def _line(slope, peak_at, n=41):
    """A curve rising at ``slope`` kN/mm to its peak at ``peak_at`` mm, then
    falling to half."""
    u = np.linspace(0.0, 2 * peak_at, n)
    P = np.where(u <= peak_at, slope * u, slope * peak_at * (1.0 - 0.5 * (u - peak_at) / peak_at))
    return pd.DataFrame(dict(displacement_mm=u, load_kN=P))


def test_summary_table_changes_against_the_reference_of_the_same_level():
    """A case's change is against the reference at its own precompression:
    11 kN against 10 kN at 0 MPa is +10 %, 18 kN against 20 kN at 0.15 MPa
    -10 %; the reference itself 0 %.  The initial stiffness is the slope of
    the pre-peak line between 10 % and 40 % of the peak: 25 kN/mm."""
    results = {"reference_sv0.0": _row(P_max_kN=10.0), "half_rate_sv0.0": _row(P_max_kN=11.0),
               "reference_sv0.15": _row(sigma_v_mpa=0.15, P_max_kN=20.0),
               "half_rate_sv0.15": _row(sigma_v_mpa=0.15, P_max_kN=18.0)}
    curves = {run: _line(25.0, 0.4) for run in results}
    t = summary_table(results, curves).set_index("run")
    assert t.loc["half_rate_sv0.0", "P_max_change_vs_reference_pct"] == pytest.approx(10.0)
    assert t.loc["half_rate_sv0.15", "P_max_change_vs_reference_pct"] == pytest.approx(-10.0)
    assert t.loc["reference_sv0.15", "P_max_change_vs_reference_pct"] == 0.0
    assert t.loc["half_rate_sv0.15", "case"] == "half_rate"
    np.testing.assert_allclose(t.initial_stiffness_kN_per_mm, 25.0, rtol=1e-12)
    assert list(t.sigma_v_mpa) == sorted(t.sigma_v_mpa)


def test_initial_stiffness_needs_two_points_in_its_window():
    """With fewer than two points between 10 % and 40 % of the peak there is
    no slope to fit: NaN, not a number from one point."""
    c = pd.DataFrame(dict(displacement_mm=[0.0, 1.0, 2.0], load_kN=[0.0, 10.0, 5.0]))
    assert math.isnan(initial_stiffness(c))


def test_hard_cases_table_half_rate_change_and_expected_mode():
    """A half-rate rerun's change is against its own case (9.9 kN against
    10 kN: -1 %); a case's mode is as expected when it is the one its
    strengths call for, or when any mode will do."""
    results = {"ftj_1.2": _row(P_max_kN=10.0, failure_mode="joint"),
               "ftj_1.2_half_rate": _row(P_max_kN=9.9, failure_mode="brick"),
               "sv_1": _row(P_max_kN=17.0, failure_mode="brick")}
    t = hard_cases_table(results, {"ftj_1.2": "brick", "sv_1": "any"}).set_index("run")
    assert math.isnan(t.loc["ftj_1.2", "half_rate_change_pct"])
    assert t.loc["ftj_1.2_half_rate", "half_rate_change_pct"] == pytest.approx(-1.0)
    assert t.loc["ftj_1.2_half_rate", "case"] == "ftj_1.2"
    assert t.mode_as_expected.tolist() == [False, True, True]


@pytest.mark.parametrize("P, ok, mode, good", [
    (10.19, True, "joint", True),      # +1.9 %: within the tolerance
    (10.21, True, "joint", False),     # +2.1 %: beyond it
    (9.81, True, "joint", True),       # -1.9 %
    (10.0, True, "brick", False),      # the same load, another mode
    (10.0, False, "joint", False),     # a run that did not end ok
])
def test_reduced_table_good_enough_rule(P, ok, mode, good):
    """A reduced model is good enough when it ended ok, its P_max is within
    the tolerance (2 %) of the full model's and its failure mode is the
    full model's; its speed-up is the full model's run time over its own."""
    results = {("c", "full"): _row(P_max_kN=10.0, wall_time_s=8.0), ("c", "rigid"): _row(
        P_max_kN=P, ok=ok, failure_mode=mode, wall_time_s=2.0)}
    scene = SimpleNamespace(value=lambda setting: {"materials.joints.ft": 0.3e6}[setting])
    t = reduced_table(results, 0.02, {run: scene for run in results}).set_index("model")
    assert t.loc["rigid", "f_tj_mpa"] == 0.3
    assert t.loc["rigid", "change_pct"] == pytest.approx(100.0 * (P / 10.0 - 1.0))
    assert t.loc["rigid", "speedup"] == 4.0 and t.loc["full", "speedup"] == 1.0
    assert bool(t.loc["rigid", "good_enough"]) is good


def test_specimen_table_triplet_closed_forms():
    """Triplet: peak shear stress c + sigma tan(phi) = 0.36 + 0.2 tan(35 deg)
    MPa, residual sigma tan(phi); the end stress is the stress at the peak
    times the mean load over the last tenth of the displacement over the
    peak load (a plateau at 0.4 of the peak here)."""
    u = np.linspace(0.0, 1.0, 101)
    load = np.where(u < 0.5, 20.0 * u, 4.0)                       # peak 10 kN, plateau 4 kN
    curves = {"trip": pd.DataFrame(dict(displacement_mm=u, load_kN=load))}
    joints = SimpleNamespace(c=np.array([0.36e6, 0.36e6]), phi=np.array([35.0, 35.0]))
    scene = SimpleNamespace(loading=SimpleNamespace(test="triplet", precompression=SimpleNamespace(pressure=0.2e6)),
                            materials=SimpleNamespace(joints=joints), value=lambda setting: 0.3e6)
    results = {"trip": _row(sigma_v_mpa=0.2, P_max_kN=10.0, strength_mpa=0.5)}
    r = specimen_table(results, curves, {"trip": scene}).iloc[0]
    mu = math.tan(math.radians(35.0))
    assert r.peak_closed_form_mpa == pytest.approx(0.36 + 0.2 * mu, rel=1e-12)
    assert r.residual_closed_form_mpa == pytest.approx(0.2 * mu, rel=1e-12)
    assert r.end_stress_mpa == pytest.approx(0.4 * 0.5, rel=1e-12)
    assert r.peak_error == pytest.approx(0.5 / (0.36 + 0.2 * mu) - 1.0, rel=1e-12)


def test_modelform_table_against_its_baselines():
    """Each run's change is measured against the baseline of its own case
    and level: 11 kN against 10 kN is +10 %, 9 against 12 is -25 %; a
    changed failure mode is flagged; the baseline's own change is 0."""
    from masonrydem.analysis.validation import modelform_table
    from masonrydem.pipeline import plan

    def row(P, mode="joint"):
        return dict(P_max_kN=P, failure_mode=mode, status="load_drop", steps=1000)
    results = {("joint", 0.0, "baseline"): row(10.0), ("joint", 0.0, "strip_1"): row(11.0),
               ("joint", 0.5, "baseline"): row(12.0), ("joint", 0.5, "strip_1"): row(9.0, "brick")}
    assumptions = [{"name": "strip", "what": "", "why": "", "options": [{"label": "40 mm", "overrides": []}]}]
    labels = plan.modelform_labels({"modelform": {"assumptions": assumptions}})
    t = modelform_table(results, labels).set_index(["sigma_v_mpa", "assumption"])
    assert t.loc[(0.0, "strip"), "change_pct"] == pytest.approx(10.0)
    assert t.loc[(0.5, "strip"), "change_pct"] == pytest.approx(-25.0)
    assert t.loc[(0.0, "baseline"), "change_pct"] == 0.0 and t.loc[(0.0, "strip"), "option"] == "40 mm"
    assert t.loc[(0.5, "strip"), "mode_changed"] and not t.loc[(0.0, "strip"), "mode_changed"]
