"""The workflow's plan (masonrydem.plan): run ids and the scene overrides of
each simulation job, from small configs with known answers and from the
project's own config."""
import pytest
import yaml

from masonrydem import plan

NUMERICS = ["numerics.cells=[8, 6, 2]", "numerics.subcontact_refine=1", "loading.bending.rate=2.5e-8"]
ACCURACY = dict(
    cases=[{"name": "a", "overrides": []}, {"name": "b", "overrides": ["materials.joints.ft=1.0e6"]}],
    cells=[[1, 1, 1], [2, 1, 1]], subcontact_refine=[1, 2], path_cells=[[4, 2, 2]],
    extra_cells=[[3, 2, 1]], extra_refine=[1],
    settings=[{"name": "rate", "key": "loading.bending.rate", "values": [1e-7]},
              {"name": "safety", "key": "numerics.safety", "values": [0.5], "around": "c2x1x1_r2", "cases": ["b"]}],
    tolerance=0.02, subsample={"n_samples": 2, "precompression_mpa": [0.0], "fine": ["numerics.cells=[3, 1, 1]"]},
    scaling_courses=[2, 4])


def _config(**extra):
    return {"numerics": NUMERICS, "accuracy": ACCURACY, **extra}


def test_effective_keeps_the_last_of_each_key_in_order():
    assert plan.effective(["a=1", "b=2"], ["c=3", "a=4"], ["b=5"]) == ["c=3", "a=4", "b=5"]
    assert plan.effective([], []) == []


def test_accuracy_grid_settings_and_their_mesh_overrides():
    """The grid cells x sub-contact refinements, the extra candidates at
    their refinements, and the further path levels at the finest
    refinement only."""
    grid = plan.accuracy_grid(ACCURACY)
    assert list(grid) == ["c1x1x1_r1", "c1x1x1_r2", "c2x1x1_r1", "c2x1x1_r2", "c3x2x1_r1", "c4x2x2_r2"]
    assert grid["c4x2x2_r2"] == ["numerics.cells=[4, 2, 2]", "numerics.subcontact_refine=2"]
    assert grid["c3x2x1_r1"] == ["numerics.cells=[3, 2, 1]", "numerics.subcontact_refine=1"]


def test_one_at_a_time_settings_per_case():
    """The defaults (no override) and each setting's values; a setting
    limited to some cases runs only there, around its grid setting."""
    assert plan.accuracy_oat(ACCURACY, "a") == {"default": [], "rate_1e-07": ["loading.bending.rate=1e-07"]}
    assert plan.accuracy_oat(ACCURACY, "b")["safety_0.5"] == [
        "numerics.cells=[2, 1, 1]", "numerics.subcontact_refine=2", "numerics.safety=0.5"]
    assert plan.accuracy_baselines(_config()) == {"rate_1e-07": "default", "safety_0.5": "c2x1x1_r2"}


def test_around_must_name_a_grid_setting():
    bad = {**ACCURACY, "settings": [{"name": "s", "key": "numerics.safety", "values": [1], "around": "c9x9x9_r1"}]}
    with pytest.raises(ValueError, match="c9x9x9_r1"):
        plan.accuracy_oat(bad, "a")


def test_accuracy_runs_and_their_overrides():
    """Case a: 6 grid settings + default + rate; case b: + safety.  A mesh
    setting replaces the defaults' cells and refinement, keeps the rest."""
    runs = plan.accuracy_runs(_config())
    assert len(runs) == 8 + 9 and runs[0] == ("a", "c1x1x1_r1") and runs[-1] == ("b", "safety_0.5")
    assert plan.accuracy_cases(_config()) == ["a", "b"]
    assert plan.accuracy_overrides(_config(), "b", "c4x2x2_r2") == [
        "loading.bending.rate=2.5e-8", "materials.joints.ft=1.0e6", "numerics.cells=[4, 2, 2]",
        "numerics.subcontact_refine=2"]
    assert plan.accuracy_overrides(_config(), "a", "default") == NUMERICS
    assert plan.accuracy_overrides(_config(), "a", "rate_1e-07") == NUMERICS[:2] + ["loading.bending.rate=1e-07"]


def test_path_and_scaling_settings():
    assert plan.path_settings(_config()) == ["c1x1x1_r2", "c2x1x1_r2", "c4x2x2_r2"]
    assert plan.scaling_settings(_config()) == ["c1x1x1_r1", "c2x1x1_r1"]
    assert plan.scaling_courses(_config()) == [2, 4]
    assert plan.scaling_overrides(_config(), "4") == NUMERICS + ["geometry.courses=4"]
    assert plan.subsample_fine(_config()) == ["numerics.cells=[3, 1, 1]"]


def test_no_accuracy_study_plans_nothing_of_it():
    config = {"numerics": NUMERICS}
    assert plan.accuracy_runs(config) == [] and plan.path_settings(config) == [] and plan.scaling_settings(config) == []
    assert plan.accuracy_baselines(config) == {} and plan.subsample_fine(config) == []
    assert plan.accuracy_cases(config) == []


def test_validation_runs_and_overrides():
    config = _config(validation={"precompression_mpa": [0.0, 0.15], "cases": [
        {"name": "reference", "overrides": []}, {"name": "half_rate", "overrides": ["loading.bending.rate=1.25e-8"]}]})
    assert plan.validation_runs(config) == ["reference_sv0.0", "reference_sv0.15",
                                            "half_rate_sv0.0", "half_rate_sv0.15"]
    assert plan.validation_overrides(config, "half_rate", "0.15") == NUMERICS[:2] + [
        "loading.bending.rate=1.25e-8", "loading.precompression.pressure=150000.0"]


def test_hard_cases_with_their_half_rate_reruns():
    config = _config(hard_cases=[{"name": "x", "overrides": ["materials.joints.GI=0.3"], "expect": "joint",
                                  "half_rate": True},
                                 {"name": "y", "overrides": [], "expect": "any"}],
                     half_rate=["loading.bending.rate=1.25e-8"])
    assert plan.hard_case_jobs(config) == {"x": ["materials.joints.GI=0.3"],
                                           "x_half_rate": ["materials.joints.GI=0.3", "loading.bending.rate=1.25e-8"],
                                           "y": []}
    assert plan.hard_case_overrides(config, "x_half_rate") == NUMERICS[:2] + [
        "materials.joints.GI=0.3", "loading.bending.rate=1.25e-8"]
    assert plan.hard_case_expect(config) == {"x": "joint", "y": "any"}
    assert plan.hard_case_jobs({}) == {} and plan.hard_case_expect({}) == {}


def test_reduced_runs_and_overrides():
    config = _config(reduced={"models": {"full": [], "rigid": ["physics.blocks=rigid"]}, "tolerance": 0.02,
                              "cases": [{"name": "c1", "overrides": ["loading.precompression.pressure=0.5e6"]}]})
    assert plan.reduced_runs(config) == [("c1", "full"), ("c1", "rigid")]
    assert plan.reduced_overrides(config, "c1", "rigid") == NUMERICS + [
        "loading.precompression.pressure=0.5e6", "physics.blocks=rigid"]
    assert plan.reduced_runs({}) == []


def test_specimens_and_study_pictures():
    config = {"specimens": [{"name": "t", "scene": "t.yaml", "overrides": []}],
              "study": {"variants": ["nonspatial", "spatial"]}}
    assert plan.specimen_cases(config) == {"t": {"name": "t", "scene": "t.yaml", "overrides": []}}
    assert plan.study_pictures(config) == [("nonspatial", "joint"), ("nonspatial", "brick"),
                                           ("spatial", "joint"), ("spatial", "brick")]


def test_the_projects_config_plans_its_accuracy_study():
    """config/config.yaml: per case the 30 mesh settings (5 cells x 3
    refinements, 7 extra x 2, one further path level) and the defaults
    with 10 one-at-a-time values; ratio_tol (2) runs on joint_sv05 only,
    rate_fine (2) on brick_sv0 only: 41 + 43 + 43 = 127 runs."""
    config = yaml.safe_load(open("config/config.yaml"))
    runs = plan.accuracy_runs(config)
    assert len(runs) == 127 and len(set(runs)) == 127
    assert {s for c, s in runs if c == "joint_sv0"} >= {"c16x8x8_r4", "c8x6x2_r2", "default", "rate_1e-07"}
    assert ("joint_sv05", "ratio_tol_1e-06") in runs and ("joint_sv0", "ratio_tol_1e-06") not in runs
    assert plan.accuracy_overrides(config, "brick_sv0", "rate_fine_6.25e-09")[-3:] == [
        "numerics.cells=[12, 6, 6]", "numerics.subcontact_refine=2", "loading.bending.rate=6.25e-09"]
