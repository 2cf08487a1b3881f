"""tools/compare_results.py, the verdict of `make reproduce`: runs matched
by their keys, compared exactly, every difference and missing run named."""
import importlib.util
from pathlib import Path

import pandas as pd

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
    assert "study runs: 3 of 3 identical" in out and "validation runs: not rerun" in out
    assert "REPRODUCED" in out and "NOT" not in out


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
