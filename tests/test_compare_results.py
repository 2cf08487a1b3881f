"""tools/compare_results.py, the verdict of `make reproduce`: the committed
folder says what is expected (every study in it, every table of each);
runs matched by their keys and compared exactly, derived tables and the
predictor value by value; every difference and every missing run, table
or study named, and any of them fails."""
import importlib.util
import json
from pathlib import Path

import pandas as pd
import pytest
import yaml

spec = importlib.util.spec_from_file_location("compare_results", Path("tools/compare_results.py"))
compare_results = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare_results)


def _results(root, p_max, steps=(100, 200, 300)):
    runs = pd.DataFrame({"variant": ["nonspatial"] * 3, "sigma_v_mpa": [0.0, 0.0, 0.5], "sample": [0, 1, 0],
                         "P_max_kN": p_max, "steps": list(steps), "failure_mode": ["joint", "brick", "joint"],
                         "status": ["load_drop"] * 3, "wall_time_s": [1.0, 2.0, 3.0]})
    (root / "study").mkdir(parents=True)
    runs.to_parquet(root / "study" / "runs.parquet")
    return root


def test_identical_runs_reproduce_whatever_their_order_and_wall_times(tmp_path, capsys):
    a = _results(tmp_path / "a", [12.5, 14.0, float("nan")])
    b = _results(tmp_path / "b", [12.5, 14.0, float("nan")])
    runs = pd.read_parquet(b / "study" / "runs.parquet")
    runs.iloc[::-1].assign(wall_time_s=9.0).to_parquet(b / "study" / "runs.parquet")
    assert compare_results.main([str(a), str(b)]) == 0
    out = capsys.readouterr().out
    # the committed folder holds no validation table: none is expected, none named
    assert "study runs: 3 of 3 identical" in out and "validation runs" not in out
    assert "REPRODUCED: 1 study, 1 table rerun" in out and "NOT" not in out


def test_a_changed_value_or_a_missing_run_fails_and_is_named(tmp_path, capsys):
    a = _results(tmp_path / "a", [12.5, 14.0, 15.0])
    b = _results(tmp_path / "b", [12.5, 14.000001, 15.0], steps=(100, 200, 301))
    assert compare_results.main([str(a), str(b)]) == 1
    out = capsys.readouterr().out
    assert "study runs: 1 of 3 identical; 2 differ or are missing" in out and "NOT REPRODUCED: 2 runs" in out
    runs = pd.read_parquet(b / "study" / "runs.parquet")
    runs.iloc[:2].to_parquet(b / "study" / "runs.parquet")
    assert compare_results.main([str(a), str(b)]) == 1
    assert "left_only" in capsys.readouterr().out


def test_runs_are_matched_by_the_study_s_own_level_column(tmp_path, capsys):
    """A study that calls its level p (statistics.csv's second column
    p_mpa, no sigma_v_mpa in its runs): its runs are matched by p_mpa; a
    run moved to another level is a difference."""
    for name in ("a", "b"):
        root = _results(tmp_path / name, [12.5, 14.0, 15.0])
        runs = pd.read_parquet(root / "study" / "runs.parquet").rename(columns={"sigma_v_mpa": "p_mpa"})
        if name == "b":
            runs.loc[2, "p_mpa"] = 0.25
        runs.to_parquet(root / "study" / "runs.parquet")
        pd.DataFrame(dict(variant=["nonspatial"], p_mpa=[0.0], mode=["all"], count=[2])).to_csv(
            root / "study" / "statistics.csv", index=False)
    assert compare_results.main([str(tmp_path / "a"), str(tmp_path / "b")]) == 1
    out = capsys.readouterr().out
    assert "study runs: 2 of 4 identical; 2 differ or are missing" in out and "p_mpa" in out


def test_a_copied_table_is_not_counted_as_reproduced(tmp_path, capsys):
    a = _results(tmp_path / "a", [12.5, 14.0, 15.0])
    b = _results(tmp_path / "b", [12.5, 14.0, 15.0])
    assert compare_results.main([str(a), str(b), "--copied", "study/runs.parquet"]) == 0
    out = capsys.readouterr().out
    assert "study runs: not rerun (copied from the committed results)" in out and "identical" not in out


def test_a_derived_table_that_differs_is_named_value_by_value(tmp_path, capsys):
    """Runs identical, but the statistics differ: one mean in its fifth
    digit, one row only in the reproduction; the verdict names the table,
    the row, the column and both values, and fails."""
    a = _results(tmp_path / "a", [12.5, 14.0, 15.0])
    b = _results(tmp_path / "b", [12.5, 14.0, 15.0])
    st = pd.DataFrame(dict(variant="nonspatial", sigma_v_mpa=[0.0, 0.5], mode="all", P_max_mean_kN=[12.34, 15.0],
                           equation=["x", "y"]))
    st.to_csv(a / "study" / "statistics.csv", index=False)
    st.to_csv(b / "study" / "statistics.csv", index=False)
    assert compare_results.main([str(a), str(b)]) == 0
    assert "statistics (study/statistics.csv): identical" in capsys.readouterr().out
    changed = pd.concat([st.assign(P_max_mean_kN=[12.341, 15.0]),
                         pd.DataFrame(dict(variant=["spatial"], sigma_v_mpa=[0.0], mode=["all"], P_max_mean_kN=[1.0],
                                           equation=["z"]))])
    changed.to_csv(b / "study" / "statistics.csv", index=False)
    assert compare_results.main([str(a), str(b)]) == 1
    out = capsys.readouterr().out
    assert "statistics (study/statistics.csv): 2 values differ" in out
    assert "('nonspatial', 0.0, 'all'), P_max_mean_kN: committed 12.34, now 12.341" in out
    assert "('spatial', 0.0, 'all'), (row): committed 'absent', now 'present'" in out
    assert "NOT REPRODUCED: 0 runs and 2 derived values differ" in out


# --- what the committed folder expects: a reproduction that lacks it fails --

SENSITIVITY = pd.DataFrame(dict(variant="nonspatial", sigma_v_mpa=[0.0, 0.5], mode="all", input="f_tj",
                                index="first", S=[0.61, 0.42]))
PREDICTOR = {"study": "willis", "variant": "nonspatial", "level": "sigma_v",
             "modes": {"joint": {"intercept": 0.17096788960157472, "coef": {"f_tj": 4.9168, "f_tu": 0.0318}, "n": 297},
                       "brick": {"intercept": 0.3308, "coef": {"f_tj": 0.5099, "f_tu": 0.5221}, "n": 203}},
             "fitted_range": {"f_tj": [0.08, 0.9]}, "wallette": {"section_as_built": False, "joint_mm": 10.0}}
DESIGN = pd.DataFrame(dict(p_mpa=[0.0, 0.2], runs=20, basis="lognormal", f_xk_mpa=[1.11, 1.711],
                           gamma_M=2.5, f_xd_mpa=[0.444, 0.6844]))


def _study(root, p_max=(12.5, 14.0, 15.0), design=False):
    """A committed-like study folder: runs, a derived table (Sobol indices),
    its predictor, and where asked a design table."""
    _results(root, list(p_max))
    SENSITIVITY.to_csv(root / "study" / "sensitivity.csv", index=False)
    (root / "study" / "predictor.json").write_text(json.dumps(PREDICTOR))
    if design:
        (root / "design").mkdir()
        DESIGN.to_csv(root / "design" / "design.csv", index=False)
    return root


def _tree(root):
    """The main study with two further studies below it, as results/ holds
    them: studies/nf, and studies/waal_lab with its design table."""
    _study(root)
    _study(root / "studies" / "nf")
    _study(root / "studies" / "waal_lab", design=True)
    return root


def _run(a, b, capsys, *extra):
    code = compare_results.main([str(a), str(b), *extra])
    return code, capsys.readouterr().out


def test_a_complete_tree_of_studies_reproduces(tmp_path, capsys):
    """Three studies, each identical: each is named reproduced, and so is
    the whole (3 studies, 3 + 3 + 4 tables)."""
    a = _tree(tmp_path / "a")
    code, out = _run(a, _tree(tmp_path / "b"), capsys)
    assert code == 0, out
    for study in (f"main study, {a}", f"study {a / 'studies' / 'nf'}", f"study {a / 'studies' / 'waal_lab'}"):
        assert f"{study}: reproduced\n" in out, study
    assert "design values (design/design.csv): identical" in out and "predictor (study/predictor.json): identical" in out
    assert "REPRODUCED: 3 studies, 10 tables rerun" in out and "NOT" not in out


@pytest.mark.parametrize("new", ["empty", "absent"])
def test_an_empty_reproduction_fails_and_names_what_is_missing(tmp_path, capsys, new):
    """Nothing reproduced, in an empty folder or none at all: every
    committed table of every study is named missing, and it fails."""
    (tmp_path / "empty").mkdir()
    code, out = _run(_tree(tmp_path / "a"), tmp_path / new, capsys)
    assert code == 1
    assert "NOT REPRODUCED: 0 runs and 0 derived values differ; 10 tables missing" in out
    assert "studies/nf: NOT reproduced: the whole study is missing" in out
    assert "studies/waal_lab: NOT reproduced: the whole study is missing" in out
    assert "missing: study/runs.parquet, study/sensitivity.csv, design/design.csv, study/predictor.json" in out
    if new == "empty":      # the main study's folder is there, empty: each of its tables named
        assert f"study runs (study/runs.parquet): NOT reproduced: missing from {tmp_path / new}" in out
        assert f"predictor (study/predictor.json): NOT reproduced: missing from {tmp_path / new}" in out
    assert "\nREPRODUCED" not in out


def test_a_deleted_derived_table_fails_and_is_named_unless_copied(tmp_path, capsys):
    a, b = _tree(tmp_path / "a"), _tree(tmp_path / "b")
    (b / "study" / "sensitivity.csv").unlink()
    code, out = _run(a, b, capsys)
    assert code == 1
    assert f"Sobol indices (study/sensitivity.csv): NOT reproduced: missing from {b}" in out
    assert "main study, " + str(a) + ": NOT reproduced (1 table missing)" in out
    assert "NOT REPRODUCED: 0 runs and 0 derived values differ; 1 table missing" in out
    # named as copied (as make reproduce names the accuracy study's runs.csv): no failure
    code, out = _run(a, b, capsys, "--copied", "study/sensitivity.csv")
    assert code == 0 and "Sobol indices: not rerun (copied from the committed results)" in out


def test_a_partial_runs_table_fails_and_names_the_missing_run(tmp_path, capsys):
    """The further study's reproduction holds 2 of its 3 runs: the third
    (nonspatial, 0.5 MPa, sample 0) is named, as only the committed has it."""
    a, b = _tree(tmp_path / "a"), _tree(tmp_path / "b")
    runs = b / "studies" / "nf" / "study" / "runs.parquet"
    pd.read_parquet(runs).iloc[:2].to_parquet(runs)
    code, out = _run(a, b, capsys)
    assert code == 1
    nf = out[out.index("studies/nf:"):out.index("studies/waal_lab:")]
    assert "studies/nf: NOT reproduced" in nf and "study runs: 2 of 3 identical; 1 differ or are missing" in nf
    missing = [x.split() for x in nf.splitlines() if "left_only" in x]
    assert len(missing) == 1 and missing[0][:3] == ["nonspatial", "0.5", "0"], nf
    assert "NOT REPRODUCED: 1 runs and 0 derived values differ" in out
    # a runs table without a compared column cannot be compared: named, and it fails
    pd.read_parquet(runs).drop(columns="status").to_parquet(runs)
    code, out = _run(a, b, capsys)
    assert code == 1 and "study runs (study/runs.parquet): NOT reproduced: \"['status'] not in index\"" in out
    assert "NOT REPRODUCED: 0 runs and 0 derived values differ; 1 table missing" in out


def test_a_missing_further_study_fails_and_is_named(tmp_path, capsys):
    a, b = _tree(tmp_path / "a"), _study(tmp_path / "b")      # the main study alone
    _study(b / "studies" / "waal_lab", design=True)
    code, out = _run(a, b, capsys)
    assert code == 1
    assert f"study {a / 'studies' / 'nf'}: NOT reproduced: the whole study is missing" in out
    assert "studies/waal_lab: reproduced" in out
    assert "NOT REPRODUCED: 0 runs and 0 derived values differ; 3 tables missing" in out


def test_a_missing_or_changed_predictor_value_fails_and_is_named(tmp_path, capsys):
    """The predictor compared value by value at the derived tables'
    tolerance: a change of 1e-6 relative differs, one of 1e-12 does not;
    a text differs exactly; a value only one side has differs; the file
    missing is named."""
    a, b = _study(tmp_path / "a"), _study(tmp_path / "b")
    p = json.loads(json.dumps(PREDICTOR))
    p["modes"]["joint"]["intercept"] *= 1 + 1e-12
    p["modes"]["brick"]["coef"]["f_tu"] *= 1 + 1e-6
    p["variant"] = "spatial"
    p["fitted_range"]["f_tj"][1] = 0.91
    del p["wallette"]["section_as_built"]
    (b / "study" / "predictor.json").write_text(json.dumps(p))
    code, out = _run(a, b, capsys)
    assert code == 1
    assert "predictor (study/predictor.json): 4 values differ" in out
    assert "modes/brick/coef/f_tu: committed 0.5221, now 0.5221005221" in out
    assert "variant: committed 'nonspatial', now 'spatial'" in out
    assert "fitted_range/f_tj/1: committed 0.9, now 0.91" in out
    assert "wallette/section_as_built: committed False, now '(absent)'" in out
    assert "modes/joint/intercept" not in out
    (b / "study" / "predictor.json").unlink()
    code, out = _run(a, b, capsys)
    assert code == 1 and "predictor (study/predictor.json): NOT reproduced: missing from" in out


def test_a_changed_characteristic_strength_of_the_design_table_fails(tmp_path, capsys):
    """waal_lab's design table: f_xk at 0.2 MPa one in its fourth digit
    off; the study, table, row, column and both values are named."""
    a, b = _tree(tmp_path / "a"), _tree(tmp_path / "b")
    DESIGN.assign(f_xk_mpa=[1.11, 1.712]).to_csv(b / "studies" / "waal_lab" / "design" / "design.csv", index=False)
    code, out = _run(a, b, capsys)
    assert code == 1
    lab = out[out.index("studies/waal_lab:"):]
    assert "studies/waal_lab: NOT reproduced" in lab and "design values (design/design.csv): 1 values differ" in lab
    assert "0.2, f_xk_mpa: committed 1.711, now 1.712" in lab
    assert "NOT REPRODUCED: 0 runs and 1 derived values differ" in out


def test_a_committed_folder_with_nothing_to_compare_fails(tmp_path, capsys):
    (tmp_path / "a").mkdir()
    code, out = _run(tmp_path / "a", _tree(tmp_path / "b"), capsys)
    assert code == 1 and "holds none of the tables compared" in out


def test_the_committed_results_against_nothing_fail_naming_every_study(tmp_path, capsys):
    """The repository's results/ against an empty folder (seconds: no table
    is read): it fails, and every study a workflow config of the
    repository writes (config/studies/**/*_workflow.yaml's results) is
    named missing whole, with the main study's runs and predictor."""
    (tmp_path / "empty").mkdir()
    code, out = _run(Path("results"), tmp_path / "empty", capsys)
    assert code == 1
    folders = [yaml.safe_load(f.read_text())["results"] for f in sorted(Path("config/studies").rglob("*_workflow.yaml"))]
    assert len(folders) >= 8
    for folder in folders:
        assert f"study {folder}: NOT reproduced: the whole study is missing" in out, folder
    assert "study runs (study/runs.parquet): NOT reproduced: missing" in out
    assert "predictor (study/predictor.json): NOT reproduced: missing" in out
    assert "design/design.csv" in out
    assert "\nREPRODUCED" not in out
