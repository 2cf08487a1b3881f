"""A corpus of malformed inputs, every one refused before any
computation with exit code 2 and a message naming the setting as the user
wrote it; a run that raises still writes its row (exit 3), a run that ends
not ok exits 1; the workflow's config is refused at planning."""
import copy
import math
import os
import subprocess
import sys
from pathlib import Path

import numba
import pandas as pd
import pytest
import yaml

from masonrydem import cli
from masonrydem.errors import InputError
from masonrydem.pipeline.check import check_config
from masonrydem.pipeline import plan
from masonrydem.specimen import protocol, row as results
from masonrydem.scene import MAX_BYTES, read_scene
from masonrydem.scene import SCHEMA, build_scene, validate_scene
from masonrydem.scene import model_size
from masonrydem.specimen.build import build

WILLIS = "config/scenes/willis.yaml"
TEXT = Path(WILLIS).read_text()
# a coarse wallette loaded fast, with the local damping it was chosen at
# (0.8: at the default 0.4 this rate's ramp overshoots the peak)
SMALL = ["--set", "numerics.cells=[3, 1, 1]", "--set", "loading.bending.rate=2e-7",
         "--set", "loading.bending.ramp_steps=500", "--set", "numerics.damping=0.8"]


def _scene(tmp_path, content, name="scene.yaml"):
    """A scene file of ``content`` (str: UTF-8; bytes: as is)."""
    path = tmp_path / name
    path.write_bytes(content.encode() if isinstance(content, str) else content)
    return str(path)


def _bomb(levels=9):
    """The billion laughs: each level ten aliases of the one before."""
    lines = ["name: bomb", "x0: &x0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    lines += [f"x{i}: &x{i} [{', '.join([f'*x{i - 1}'] * 10)}]" for i in range(1, levels)]
    return "\n".join(lines) + "\n"


def _flow_bomb(levels=9):
    """The same as one YAML flow sequence (a --set value)."""
    items = ["&a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    items += [f"&a{i} [{', '.join([f'*a{i - 1}'] * 10)}]" for i in range(1, levels)]
    return f"[{', '.join(items)}]"


# (id, scene file content or None for willis.yaml, extra CLI arguments, field
# named, words of the message); "{tmp}" in an argument is the test's folder
CASES = [
    # scene files that are not UTF-8 text
    ("binary", bytes(range(256)) * 4, [], "scene", "not UTF-8"),
    ("latin1", TEXT.replace("description: Willis", "description: Ziegel aus Köln, Willis").encode("latin-1"), [],
     "scene", "not UTF-8"),
    ("utf16", TEXT.encode("utf-16"), [], "scene", "not UTF-8"),
    ("nul_bytes", "name: a\0b\n", [], "scene", "not valid YAML"),
    ("not_yaml", "name: [willis\n", [], "scene", "not valid YAML"),
    ("not_a_mapping", "- name\n- willis\n", [], "scene", "mapping"),
    ("empty_file", "", [], "scene", "mapping"),
    ("too_large", "name: big\ndescription: " + "x" * MAX_BYTES + "\n", [], "scene", "larger than"),
    ("a_folder", None, ["--set", "name=x", "SCENE={tmp}"], "scene", "cannot read"),
    ("missing", None, ["SCENE={tmp}/nope.yaml"], "scene", "cannot read"),
    # --set
    ("set_malformed_value", None, ["--set", "numerics.cells=[3, 1"], "numerics.cells", "not valid YAML"),
    ("set_into_scalar", None, ["--set", "name.first=x"], "name.first", "not a section"),
    ("set_into_list", None, ["--set", "loading.bending.supports_x.0=0.1"], "loading.bending.supports_x.0", "not a section"),
    ("set_without_value", None, ["--set", "numerics.cells"], "--set", "path.to.key=value"),
    ("set_empty_key", None, ["--set", "numerics..cells=3"], "--set", "dotted path"),
    ("set_unknown_key", None, ["--set", "numerics.celss=[3, 1, 1]"], "numerics.celss", "did you mean 'cells'?"),
    ("set_alias_bomb", None, ["--set", "materials.per_unit.E=" + _flow_bomb()], "materials.per_unit.E.4", "alias"),
    # models far too large for the memory
    ("too_many_cells", None, ["--set", "numerics.cells=[1001, 1000, 1000]"], "numerics.cells", "GB of memory"),
    ("too_fine_subcontacts", None, ["--set", "numerics.subcontact_refine=100000"], "numerics.subcontact_refine",
     "sub-contacts"),
    ("too_large_a_wall", None, ["--set", "geometry.courses=100000000000"], "geometry.courses", "GB of memory"),
    ("too_many_curve_points", None, ["--set", "outputs.curve_points=1000000000"], "outputs.curve_points",
     "maximum"),
    # YAML alias bombs, recursion, duplicate keys
    ("alias_bomb", _bomb(), [], "x4", "alias"),
    ("recursive_alias", "name: r\ndescription: &d [*d]\n", [], "description.0", "itself"),
    ("nested_too_deeply", "name: deep\ndescription: " + "[" * 3000 + "]" * 3000 + "\n", [], "scene", "nested"),
    ("duplicate_key", TEXT.replace("    E: 15.0e9\n", "    E: 15.0e9\n    E: 12.0e9\n"), [],
     "materials.units.E", "twice"),
    ("duplicate_section", TEXT + "outputs:\n  state: true\n", [], "outputs", "twice"),
    # --out
    ("out_is_a_file", None, ["OUT={tmp}/file"], "--out", "is a file"),
    ("out_under_a_file", None, ["OUT={tmp}/file/run"], "--out", "under"),
    ("out_empty", None, ["OUT="], "--out", "empty"),
    ("out_not_writable", None, ["OUT=/sys/masonrydem_out"], "--out", "cannot write"),
    # --threads
    ("threads_above_cores", None, ["--threads", str(numba.config.NUMBA_NUM_THREADS + 1)], "--threads", "cores"),
    ("threads_zero", None, ["--threads", "0"], "--threads", "between 1"),
    # four-point bending geometry
    ("load_outside_supports", None, ["--set", "loading.bending.loads_x=[0.1, 0.67]"], "loading.bending.loads_x.0",
     "between the supports"),
    ("loads_beyond_supports", None, ["--set", "loading.bending.loads_x=[0.41, 0.98]"], "loading.bending.loads_x.1",
     "between the supports"),
    ("support_between_loads", None, ["--set", "loading.bending.supports_x=[0.135, 0.5, 0.945]"],
     "loading.bending.supports_x.1", "between the loads"),
    ("supports_and_loads_swapped", None, ["--set", "loading.bending.supports_x=[0.41, 0.67]",
                                          "--set", "loading.bending.loads_x=[0.135, 0.945]"],
     "loading.bending.loads_x.0", "between the supports"),
    ("one_support", None, ["--set", "loading.bending.supports_x=[0.135]"], "loading.bending.supports_x",
     "too short"),
    # NaN and infinities, named as the scene writes them
    ("nan_set", None, ["--set", "materials.units.E=.nan"], "materials.units.E", "finite"),
    ("inf_set", None, ["--set", "loading.bending.rate=.inf"], "loading.bending.rate", "finite"),
    ("overflow_set", None, ["--set", "materials.joints.ft=1e400"], "materials.joints.ft", "finite"),
    ("huge_integer", None, ["--set", "materials.units.E=1" + "0" * 400], "materials.units.E", "finite"),
    ("nan_in_file", TEXT.replace("phi: 35.0                 # not given", "phi: .nan                 # not given"),
     [], "materials.units.phi", "finite"),
    ("nan_in_a_list", None, ["--set", "materials.per_unit.E=" + str([1e9] * 23 + [".nan"]).replace("'", "")],
     "materials.per_unit.E.23", "finite"),
    # strip stiffness
    ("strip_stiffness_1e9", None, ["--set", "loading.bending.strip_stiffness_ratio=1e9"],
     "loading.bending.strip_stiffness_ratio", "maximum"),
]


@pytest.fixture
def no_simulation(monkeypatch):
    """Fails any case that gets as far as a simulation (the CLI would then
    report an internal error, 3, not 2)."""
    def refuse(*a, **k):
        raise AssertionError("a simulation started")
    monkeypatch.setattr(protocol, "simulate", refuse)
    monkeypatch.setattr(protocol, "build", refuse)


def _argv(tmp_path, content, extra):
    (tmp_path / "file").write_text("not a folder")
    scene = _scene(tmp_path, content) if content is not None else WILLIS
    out, args = str(tmp_path / "out"), []
    for a in extra:
        a = a.replace("{tmp}", str(tmp_path))
        if a.startswith("OUT="):
            out = a[4:]
        elif a.startswith("SCENE="):
            scene = a[6:]
        else:
            args.append(a)
    return ["run", scene, *args, "--out", out, "--quiet"], out


@pytest.mark.parametrize("content, extra, field, words", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_refused_naming_the_field(tmp_path, capsys, no_simulation, content, extra, field, words):
    if "OUT=/sys/masonrydem_out" in extra and not Path("/sys").is_dir():
        pytest.skip("no /sys")
    argv, out = _argv(tmp_path, content, extra)
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"masonrydem: invalid input: {field}: ") and words in err, err
    assert "Traceback" not in err
    assert not Path(out or ".", "result.parquet").exists()
    assert not (tmp_path / "out").exists() or field == "--out"


def test_out_in_a_read_only_folder(tmp_path, capsys, no_simulation, monkeypatch):
    """A folder the user may not write into (read-only: 0o555) is refused
    before any computation.  Root writes into it all the same, so for root
    the refusal the file system would give anyone else is made here."""
    import tempfile
    (tmp_path / "ro").mkdir(mode=0o555)
    if os.geteuid() == 0:
        def refuse(*a, **k):
            raise PermissionError(13, "Permission denied")
        monkeypatch.setattr(tempfile, "TemporaryFile", refuse)
    assert cli.main(["run", WILLIS, "--out", str(tmp_path / "ro" / "run")]) == 2
    assert "--out: cannot write" in capsys.readouterr().err


@pytest.mark.parametrize("case", ["size", "alias_bomb"])
def test_large_inputs_are_refused_in_a_fresh_process(tmp_path, case):
    """The command itself (not only in-process): exit 2, no traceback, no
    output; a hang (the old behaviour: a MemoryError after seconds, or tens
    of seconds of alias expansion) trips the generous timeout."""
    scene, extra = (WILLIS, ["--set", "numerics.cells=[1001, 1000, 1000]"]) if case == "size" else (
        _scene(tmp_path, _bomb()), [])
    r = subprocess.run([sys.executable, "-m", "masonrydem.cli", "run", scene, *extra, "--out", str(tmp_path / "out")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


def test_the_scenes_of_the_project_are_accepted():
    for path in ("config/scenes/willis.yaml", "config/scenes/tension.yaml", "config/scenes/triplet.yaml"):
        build_scene(path)
    build_scene(WILLIS, ["loading.bending.strip_stiffness_ratio=100", "outputs.curve_points=100000"])


def test_size_estimate_bounds_the_model_built():
    """model_size counts what build makes: its nodes, tetrahedra and linear
    cells exactly, its sub-contacts from above (within a factor 2)."""
    for overrides in (["physics.blocks=elasto-plastic", "numerics.cells=[3, 1, 1]", "numerics.subcontact_refine=2"],
                      ["physics.blocks=potential-crack", "numerics.elastic_element=hex8i", "numerics.cells=[2, 2, 1]"],
                      ["physics.blocks=rigid", "numerics.subcontact_refine=3"],
                      ["physics.blocks=elastic", "numerics.cells=[4, 2, 2]", "geometry.bond_offset=0.25"], []):
        scene = build_scene(WILLIS, overrides)
        a = build(scene).assembly
        size = model_size(scene.geometry, scene.physics, scene.discretization, scene.loading)
        assert (size["nodes"], size["tetrahedra"], size["cells"]) == (
            a.nodes.x0.shape[0], a.zones.tets.shape[0], a.cells.nodes.shape[0]), overrides
        subs = a.joints.nodes.shape[0] + a.bearings.nodes.shape[0]
        assert subs <= size["sub_contacts"] <= 2 * subs, overrides


def test_anchors_aliases_and_merge_keys_within_limits_are_read(tmp_path):
    """Anchors and aliases as such are fine; so is a merge key whose
    mapping sets a key again (the scene schema itself: the tension test
    merges the drive's settings and sets its own rate)."""
    ks = "    ks_ratio: 0.4             # k_s = 0.4 k_n\n"
    text = TEXT.replace("    E: 15.0e9\n", "    E: &E 15.0e9\n").replace(
        ks, ks + "  per_unit: {E: [" + ", ".join(["*E"] * 24) + "]}\n")
    scene = read_scene(_scene(tmp_path, text))
    validate_scene(scene)       # as build_scene: the mapping validated, its defaults filled in
    assert scene["materials"]["per_unit"]["E"] == [15.0e9] * 24
    assert SCHEMA["properties"]["loading"]["properties"]["tension"]["properties"]["rate"]["default"] == 2.0e-9


# --- exit codes of runs that go wrong --------------------------------------------
def test_internal_error_writes_its_row_and_exits_3(tmp_path, monkeypatch, capsys):
    def boom(scene, progress=True):
        raise RuntimeError("boom")
    monkeypatch.setattr(protocol, "simulate", boom)
    assert cli.main(["run", WILLIS, "--out", str(tmp_path), "--quiet"]) == 3
    assert "RuntimeError: boom" in capsys.readouterr().err
    row = pd.read_parquet(tmp_path / "result.parquet").iloc[0]
    assert row["status"] == "error" and not row["ok"] and row["message"] == "RuntimeError: boom"
    assert row["scene"] == "willis" and row["cells"] == "x".join(map(str, build_scene(WILLIS).discretization.cells))
    curve = pd.read_parquet(tmp_path / "curve.parquet")
    assert len(curve) == 0 and list(curve.columns) == list(results.CURVE_COLUMNS)


def test_a_run_that_ends_not_ok_exits_1(tmp_path, monkeypatch, capsys):
    row = dict(status="max_steps", ok=False, message="reached 300 steps", P_max_kN=math.nan,
               disp_at_peak_mm=math.nan, strength_mpa=math.nan, classification="none", steps=300, wall_time_s=0.1)
    curve = {c: [] for c in results.CURVE_COLUMNS}
    # the simulation stubbed: no Outcome, the row and curve made of it are the ones above
    monkeypatch.setattr(protocol, "simulate", lambda scene, progress=True: None)
    monkeypatch.setattr(results, "outcome_row", lambda outcome, **labels: results.Row(**row))
    monkeypatch.setattr(results, "curve", lambda outcome: curve)
    assert cli.main(["run", WILLIS, "--out", str(tmp_path), "--quiet"]) == 1
    assert "ended not ok (max_steps)" in capsys.readouterr().err
    assert pd.read_parquet(tmp_path / "result.parquet").iloc[0]["status"] == "max_steps"


def test_an_unconverged_precompression_is_not_ok(tmp_path):
    """A precompression stopped by its step limit (never in equilibrium),
    then a bending stage that ends as it should: the row is not ok, and
    says why (exit 1)."""
    assert cli.main(["run", WILLIS, *SMALL, "--set", "loading.precompression.pressure=0.2e6",
                     "--set", "loading.precompression.max_steps=5", "--quiet", "--out", str(tmp_path)]) == 1
    row = pd.read_parquet(tmp_path / "result.parquet").iloc[0]
    assert row["precompression_status"] == "max_steps"
    assert row["status"] == "precompression_unconverged" and not row["ok"], row["message"]
    assert "did not reach equilibrium" in row["message"]


# --- the workflow's config ----------------------------------------------------
def _config():
    config = yaml.safe_load(open("config/config.yaml"))
    config.setdefault("results", "results")
    return config


def test_the_projects_configs_pass_planning():
    from snakemake.utils import update_config
    check_config(_config())
    smoke = _config()
    update_config(smoke, yaml.safe_load(open("config/smoke.yaml")))
    check_config(smoke)


def _set(config, dotted, value):
    *path, last = dotted.split(".")
    node = config
    for k in path:
        node = node[int(k)] if isinstance(node, list) else node[k]
    node[int(last) if isinstance(node, list) else last] = value
    return config


@pytest.mark.parametrize("key, value, field, words", [
    ("numerics", ["numerics.cells=[0, 1, 1]"], "numerics", "numerics.cells.0"),
    ("numerics", ["numerics.safety=2"], "numerics", "numerics.safety"),
    ("numerics", ["loading.bending.loads_x=[0.05, 0.67]"], "numerics", "loading.bending.loads_x.0"),
    ("study.levels", [0.0, math.nan], "study.levels.1", "finite"),
    ("validation.precompression_mpa", [math.inf], "validation.precompression_mpa.0", "finite"),
    ("accuracy.tolerance", math.nan, "accuracy.tolerance", "finite"),
    ("validation.cases.0.overrides", ["materials.units.E=-1"], "validation.cases (", "materials.units.E"),
    ("accuracy.settings.0.values", [2.0], "accuracy (", "numerics.safety"),
    ("hard_cases", [{"name": "h", "overrides": ["name.first=x"], "expect": "any"}], "hard_cases (h)", "name.first"),
])
def test_a_config_that_makes_runs_invalid_fails_at_planning(key, value, field, words):
    config = _config()
    if key == "accuracy.settings.0.values":
        config["accuracy"]["settings"][0] = {"name": "safety", "key": "numerics.safety", "values": value}
    else:
        _set(config, key, copy.deepcopy(value))
    with pytest.raises(InputError) as e:
        check_config(config)
    assert e.value.field.startswith(field) and words in str(e.value), str(e.value)


@pytest.mark.parametrize("results", ["", "  "])
def test_an_empty_results_folder_is_refused(results):
    from snakemake.exceptions import WorkflowError
    from snakemake.utils import validate
    config = _config()
    config["results"] = results
    with pytest.raises(WorkflowError, match="results"):
        validate(config, "config/schema.yaml", set_default=True)
