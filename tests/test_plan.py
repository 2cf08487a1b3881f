"""The workflow's plan (masonrydem.pipeline.plan): run ids and the scene overrides of
each simulation job, from small configs with known answers and from the
project's own config."""
import pytest
import yaml

from masonrydem.errors import InputError
from masonrydem.pipeline.check import check_config
from masonrydem.pipeline import plan

NUMERICS = ["numerics.cells=[8, 6, 2]", "numerics.subcontact_refine=1", "loading.bending.rate=2.5e-8"]
ACCURACY = dict(
    cases=[{"name": "a", "overrides": []}, {"name": "b", "overrides": ["materials.joints.ft=1.0e6"]}],
    path={"overrides": ["loading.bending.rate=1e-8"], "cells": [[1, 1, 1], [3, 1, 1], [5, 2, 2]]},
    candidates=[{"name": "pc", "overrides": ["physics.blocks=potential-crack", "numerics.cells=[2, 2, 2]"]}],
    settings=[{"name": "rate", "key": "loading.bending.rate", "values": [1e-7]},
              {"name": "safety", "key": "numerics.safety", "values": [0.5], "around": "pc", "cases": ["b"]}],
    tolerance=0.02, subsample={"n_samples": 2, "precompression_mpa": [0.0], "fine": ["numerics.cells=[3, 1, 1]"]},
    scaling_courses=[2, 4])


def _config(**extra):
    return {"numerics": NUMERICS, "accuracy": ACCURACY, **extra}


def test_effective_keeps_the_last_of_each_key_in_order():
    assert plan.effective(["a=1", "b=2"], ["c=3", "a=4"], ["b=5"]) == ["c=3", "a=4", "b=5"]
    assert plan.effective([], []) == []


def test_accuracy_settings_per_case():
    """The path levels (the path's overrides and their cells), the
    candidates, the defaults (no override) and each one-at-a-time value; a
    setting limited to some cases runs only there, around its candidate."""
    a = plan.accuracy_settings(ACCURACY, "a")
    assert list(a) == ["path_c1x1x1", "path_c3x1x1", "path_c5x2x2", "pc", "default", "rate_1e-07"]
    assert a["path_c5x2x2"] == ["loading.bending.rate=1e-8", "numerics.cells=[5, 2, 2]"]
    assert a["rate_1e-07"] == ["loading.bending.rate=1e-07"]
    assert plan.accuracy_settings(ACCURACY, "b")["safety_0.5"] == [
        "physics.blocks=potential-crack", "numerics.cells=[2, 2, 2]", "numerics.safety=0.5"]
    assert plan.accuracy_baselines(_config()) == {"rate_1e-07": "default", "safety_0.5": "pc"}


def test_around_must_name_a_candidate_or_a_path_level():
    bad = {**ACCURACY, "settings": [{"name": "s", "key": "numerics.safety", "values": [1], "around": "nope"}]}
    with pytest.raises(ValueError, match="nope"):
        plan.accuracy_settings(bad, "a")


def test_accuracy_runs_and_their_overrides():
    """Case a: 3 path levels + 1 candidate + default + rate; case b: + safety.
    A path level replaces the defaults' rate and cells, keeps the rest."""
    runs = plan.accuracy_runs(_config())
    assert len(runs) == 6 + 7 and runs[0] == ("a", "path_c1x1x1") and runs[-1] == ("b", "safety_0.5")
    assert plan.accuracy_cases(_config()) == ["a", "b"]
    assert plan.accuracy_overrides(_config(), "b", "path_c3x1x1") == [
        "numerics.subcontact_refine=1", "materials.joints.ft=1.0e6", "loading.bending.rate=1e-8",
        "numerics.cells=[3, 1, 1]"]
    assert plan.accuracy_overrides(_config(), "a", "default") == NUMERICS
    assert plan.accuracy_overrides(_config(), "a", "rate_1e-07") == NUMERICS[:2] + ["loading.bending.rate=1e-07"]


def test_path_candidate_and_scaling_settings():
    assert plan.path_settings(_config()) == ["path_c1x1x1", "path_c3x1x1", "path_c5x2x2"]
    assert plan.candidate_settings(_config()) == ["pc"]
    assert plan.scaling_settings(_config()) == plan.path_settings(_config())
    assert plan.scaling_courses(_config()) == [2, 4]
    assert plan.scaling_overrides(_config(), "4") == NUMERICS + ["geometry.courses=4"]
    assert plan.subsample_fine(_config()) == ["numerics.cells=[3, 1, 1]"]


def test_no_accuracy_study_plans_nothing_of_it():
    config = {"numerics": NUMERICS}
    assert plan.accuracy_runs(config) == [] and plan.path_settings(config) == [] and plan.scaling_settings(config) == []
    assert plan.candidate_settings(config) == []
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


def test_modelform_runs_and_overrides():
    """Per case and level the baseline and every option of every
    assumption; an option's overrides come after the numerics, its case's
    and the level's, so that they replace what those set."""
    config = _config(modelform={
        "cases": [{"name": "joint", "overrides": []}, {"name": "brick", "overrides": ["materials.joints.ft=1.0e6"]}],
        "precompression_mpa": [0.0, 0.5],
        "assumptions": [{"name": "strip_width", "what": "", "why": "", "options": [
            {"label": "10 mm", "overrides": ["loading.bending.strip_width=0.01"]},
            {"label": "40 mm", "overrides": ["loading.bending.strip_width=0.04"]}]},
            {"name": "law", "what": "", "why": "", "options": [
                {"label": "brittle", "overrides": ["physics.joints=brittle_coulomb",
                                                   "loading.bending.rate=1e-8"]}]}]})
    runs = plan.modelform_runs(config)
    assert len(runs) == 2 * 2 * (1 + 2 + 1)
    assert runs[:4] == [("joint", 0.0, "baseline"), ("joint", 0.0, "strip_width_1"), ("joint", 0.0, "strip_width_2"),
                        ("joint", 0.0, "law_1")]
    assert plan.modelform_overrides(config, "brick", "0.5", "strip_width_2") == NUMERICS + [
        "materials.joints.ft=1.0e6", "loading.precompression.pressure=500000.0", "loading.bending.strip_width=0.04"]
    assert plan.modelform_overrides(config, "joint", "0.0", "law_1") == NUMERICS[:2] + [
        "loading.precompression.pressure=0.0", "physics.joints=brittle_coulomb", "loading.bending.rate=1e-8"]
    assert plan.modelform_overrides(config, "joint", "0.0", "baseline") == NUMERICS + [
        "loading.precompression.pressure=0.0"]
    assert plan.modelform_runs({}) == []


def test_the_projects_config_plans_its_modelform_study():
    """config/config.yaml: at least 10 assumptions x 3 levels x 2 modes
    (config 'modelform'), every option's scene accepted at planning."""
    with open("config/config.yaml") as f:
        config = yaml.safe_load(f)
    m = config["modelform"]
    assert len(m["assumptions"]) >= 10 and len(m["precompression_mpa"]) == 3 and len(m["cases"]) == 2
    assert all(a["why"] and a["what"] for a in m["assumptions"])
    check_config(config)


def test_specimens_and_study_pictures():
    config = {"specimens": [{"name": "t", "scene": "t.yaml", "overrides": []}],
              "study": {"file": "config/studies/willis.yaml"}}
    assert plan.specimen_cases(config) == {"t": {"name": "t", "scene": "t.yaml", "overrides": []}}
    assert plan.study_pictures(config) == [("nonspatial", "joint"), ("nonspatial", "brick"),
                                           ("spatial", "joint"), ("spatial", "brick")]


def test_the_config_overrides_the_study_files_samples_seed_and_levels():
    """config/smoke.yaml's study: the Willis study file with 8 samples, seed
    1 and two levels (as quantities); the study file's own otherwise."""
    base = plan.study({"study": {"file": "config/studies/willis.yaml"}})
    smoke = plan.study({"study": {"file": "config/studies/willis.yaml", "samples": 8, "seed": 1,
                                  "levels": ["0 MPa", "0.5 MPa"]}})
    assert (base.samples, base.seed, plan.study_levels({"study": {"file": "config/studies/willis.yaml"}})) == \
        (100, 20260101, [0.0, 0.075, 0.15, 0.25, 0.5])
    assert (smoke.samples, smoke.seed, smoke.levels) == (8, 1, (0.0, 0.5e6))
    assert smoke.variables == base.variables and smoke.rules == base.rules
    with pytest.raises(InputError) as e:
        plan.study({"study": {"file": "config/studies/willis.yaml", "levels": [0.15]}})
    assert e.value.field == "study.levels.0" and "did you mean '0.15 MPa'?" in str(e.value)
    # a level given twice in other words would make two runs folders of one level: refused
    with pytest.raises(InputError) as e:
        plan.study({"study": {"file": "config/studies/willis.yaml", "levels": ["0 MPa", "0.1 N/mm2", "100 kPa"]}})
    assert e.value.field == "study.levels.2" and "is the level '0.1 N/mm2' (study.levels.1) again" in str(e.value)


def test_the_projects_config_plans_its_accuracy_study():
    """config/config.yaml: per case the 8 path levels, 14 candidates, the
    defaults, 11 one-at-a-time values (plus two ratio_tol values under
    precompression) and the 17x8x6 path level at half the paths'
    rate: 35 + 37 + 35 + 37 + 37 = 181 runs; the path levels run the
    elasto-plastic model at the paths' rate (2.5e-8 m per step, their
    overrides), the brick cases' at half of it (their path_overrides), with
    the damping pinned (0.8): the references (the path levels and the runs
    around one, 45) are the same computation whatever the defaults, and
    the coarsest level of each case is rerun to check their table."""
    from masonrydem.scene import build_scene
    config = yaml.safe_load(open("config/config.yaml"))
    runs = plan.accuracy_runs(config)
    assert len(runs) == 181 and len(set(runs)) == 181
    knee = build_scene(config["scene"], plan.accuracy_overrides(config, "mixed_sv05", "pc_c4x3x2_head_rate15"))
    assert knee.integration.damping == 0.4 and knee.loading.drive.rate == 1.125e-7
    former = build_scene(config["scene"], plan.accuracy_overrides(config, "mixed_sv05", "pc_c4x3x2_head_d08_half"))
    assert former.integration.damping == 0.8 and former.loading.drive.rate == 3.75e-8
    references = plan.reference_runs(config)
    assert len(references) == 45 and set(references) <= set(runs)
    assert all(s.startswith("path_") for c, s in references)
    assert plan.reference_checks(config) == [(c, "path_c7x3x2") for c in plan.accuracy_cases(config)]
    for case, setting in references:
        assert build_scene(config["scene"], plan.accuracy_overrides(config, case, setting)).integration.damping == 0.8
    assert {s for c, s in runs if c == "joint_sv0"} >= {"path_c17x8x6", "pc_c6x3x2_r121", "default", "rate_1.5e-07"}
    assert ("joint_sv05", "ratio_tol_1e-05") in runs and ("joint_sv0", "ratio_tol_1e-05") not in runs
    joint = build_scene(config["scene"], plan.accuracy_overrides(config, "joint_sv0", "path_c17x8x6"))
    assert joint.loading.drive.rate == 2.5e-8 and joint.physics.blocks == "elasto-plastic"
    o = plan.accuracy_overrides(config, "brick_sv0", "path_c17x8x6")
    assert "loading.bending.rate=1.25e-8" in o and "physics.blocks=elasto-plastic" in o
    assert o[-1] == "numerics.cells=[17, 8, 6]"
    # a setting 'around' a path level: that level's overrides, then the value
    o = plan.accuracy_overrides(config, "brick_sv0", "path_rate_6.25e-09")
    assert o[-2:] == ["numerics.cells=[17, 8, 6]", "loading.bending.rate=6.25e-09"]
    assert ("joint_sv0", "path_rate_1.25e-08") in runs and ("joint_sv0", "path_rate_6.25e-09") not in runs
