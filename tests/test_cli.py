"""`masonrydem run`: outputs, refusal of bad input, nothing lost."""
import subprocess
import sys

import pandas as pd
import pyvista as pv
import pytest

WILLIS = "config/scenes/willis.yaml"
# the source paper's elasto-plastic units, coarse (its final state has zones with their damage)
SMALL = ["--set", "physics.blocks=elasto-plastic", "--set", "numerics.cells=[3, 1, 1]", "--set", "loading.bending.rate=2e-7",
         "--set", "loading.bending.ramp_steps=500"]


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "masonrydem.cli", *args], capture_output=True, text=True)


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("run")
    r = _cli("run", WILLIS, *SMALL, "--out", str(out), "--state")
    assert r.returncode == 0, r.stderr
    assert "[bending] step" in r.stderr or "load_drop" in r.stdout     # progress or at least the summary
    return out


def test_result_row(run_dir):
    row = pd.read_parquet(run_dir / "result.parquet")
    assert len(row) == 1
    for col in ("sigma_v_mpa", "P_max_kN", "disp_at_peak_mm",
                "strength_mpa", "failure_mode", "cracked_units", "unit_crack_fraction", "broken_joints",
                "classification", "status", "steps", "wall_time_s", "solver_version"):
        assert col in row.columns
    r = row.iloc[0]
    assert r["status"] == "load_drop" and r["ok"]
    # sigma = 6 M / (b h^2), M = 0.1375 P (docs/study.md, 2)
    assert r["strength_mpa"] == pytest.approx(6 * 0.1375 * r["P_max_kN"] * 1e-3 / (0.44 * 0.114 ** 2), rel=1e-9)


def test_curve_keeps_the_peak(run_dir):
    """The curve holds the peak's point exactly; a higher load on it is
    one the load's own unbalance disqualifies (a dynamic overshoot)."""
    row = pd.read_parquet(run_dir / "result.parquet").iloc[0]
    curve = pd.read_parquet(run_dir / "curve.parquet")
    assert 10 <= len(curve) <= 410
    assert (curve["load_kN"] == row["P_max_kN"]).sum() == 1
    from masonrydem.dem.history import PEAK_UNBALANCE
    assert (curve.loc[curve["load_kN"] > row["P_max_kN"], "unbalance"] >= PEAK_UNBALANCE).all()
    assert curve["displacement_mm"].is_monotonic_increasing


def test_state_is_readable(run_dir):
    state = pv.read(run_dir / "state.vtm")
    zones, joints = state["zones"], state["joints"]
    assert zones.n_cells == 24 * 3 * 5 and set(zones.cell_data["unit"]) == set(range(1, 25))
    assert 0 <= zones.cell_data["damage"].min() and zones.cell_data["damage"].max() <= 1
    assert set(joints.point_data["joint"]) == set(range(1, 39))
    assert "u" in zones.point_data


def test_bad_input_refused_before_computation(tmp_path):
    r = _cli("run", WILLIS, "--set", "materials.units.E=-1", "--out", str(tmp_path / "x"))
    assert r.returncode == 2
    assert "materials.units.E" in r.stderr
    assert not (tmp_path / "x").exists()


def test_failed_run_still_recorded(tmp_path):
    """A run stopped by its step limit is recorded with its status, not
    dropped (exit code 1)."""
    r = _cli("run", WILLIS, *SMALL, "--set", "loading.bending.max_steps=300", "--quiet", "--out", str(tmp_path))
    assert r.returncode == 1
    row = pd.read_parquet(tmp_path / "result.parquet").iloc[0]
    assert row["status"] == "max_steps" and not row["ok"]


def test_every_stage_reports_its_start_and_end_in_a_log(tmp_path):
    r = _cli("run", WILLIS, *SMALL, "--set", "loading.precompression.pressure=0.15e6",
             "--set", "loading.bending.max_steps=300", "--exit-zero", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    lines = [line.split("]")[0] + "] " + line.split("] ")[1].split(" ")[0] for line in r.stderr.splitlines()
             if line.startswith("[")]
    stages = [line for line in lines if not line.endswith("step")]     # the periodic lines aside
    assert stages == ["[build] 24", "[precompression] started", "[precompression] converged", "[bending] started",
                      "[bending] max_steps"]
    assert "\r" not in r.stderr                                       # no bar in a log


def test_a_terminal_gets_a_bar_redrawn_in_place():
    import io
    import types

    import numpy as np

    from masonrydem.specimen.protocol import Progress
    from masonrydem.dem.stops import Ending

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    out = Terminal()
    p = Progress("bending", share=lambda h: 0.5, stream=out)
    p.last = -np.inf
    history = types.SimpleNamespace(monitors=1, force=np.array([[2e3]]), disp=np.array([[1e-4]]),
                                    ratio=np.array([1e-3]))
    p(types.SimpleNamespace(step=100), history)
    p.end(types.SimpleNamespace(step=200), Ending("load_drop", "load fell", 200, 1.0))
    text = out.getvalue()
    assert text.startswith("[bending] started\n")
    assert "\r[bending] step      100  load    2.000 kN  disp  0.1000 mm" in text
    assert "[##########..........]  50%" in text
    assert text.rsplit("\r", 1)[1].startswith("\x1b[K[bending] load_drop at step 200: load fell (")
