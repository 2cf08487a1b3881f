"""The package in layers (docs/architecture.md): each layer imports only
from those below it, numba and the kernels inside dem alone, nothing
imports the root package, no cycle in a folder (import-linter's contracts
in pyproject.toml), no private name is imported across modules, the
solver's hash is taken by folder, the sampling's code holds nothing of the
solver, and a study of other names, levels and variants runs through
sampling, the row, the regression and predict with nothing in the code
that knows it."""
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from masonrydem import cli, sources
from masonrydem.analysis import equations as E
from masonrydem.analysis import predict
from masonrydem.pipeline import plan
from masonrydem.pipeline.fingerprint import code_fingerprint, script_modules, simulation_module
from masonrydem.specimen.row import read_json, write_json
from masonrydem.scene import build_scene
from masonrydem.study.file import load_study

ROOT = Path(__file__).parent.parent
PACKAGE = ROOT / "src" / "masonrydem"


def test_no_layer_imports_one_above_it():
    """import-linter's contracts (pyproject.toml), run as `make test` runs
    them: the layers, numba and the kernels forbidden outside dem, the
    root package protected, no cycle between siblings; all four kept."""
    exe = Path(sys.executable).with_name("lint-imports")
    r = subprocess.run([str(exe)], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "4 kept, 0 broken" in r.stdout


def test_no_private_name_is_imported_across_modules():
    """No module of the package imports another's private name (``from .m
    import _x``) or reads one through a module it imported (``m._x``)."""
    import ast
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text())
        modules = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("masonrydem")):
                found += [f"{path.name}:{node.lineno} {a.name}" for a in node.names if _private(a.name)]
                modules |= {a.asname or a.name for a in node.names}
            elif isinstance(node, ast.Import):
                modules |= {a.asname or a.name for a in node.names if a.name.startswith("masonrydem")}
        found += [f"{path.name}:{n.lineno} {n.value.id}.{n.attr}" for n in ast.walk(tree)
                  if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id in modules
                  and _private(n.attr)]
    assert not found, found


def _private(name):
    return name.startswith("_") and not name.startswith("__")


def test_every_subpackage_has_a_public_face():
    """Each folder's __init__ names its public names in __all__, and each
    of them is there: scene and dem export what the layers above use."""
    import importlib
    for folder in sorted(p.parent.name for p in PACKAGE.glob("*/__init__.py")):
        module = importlib.import_module(f"masonrydem.{folder}")
        assert module.__all__, folder
        for name in module.__all__:      # a name it holds, or a module of the folder (analysis, report, pipeline)
            assert hasattr(module, name) or (PACKAGE / folder / f"{name}.py").is_file(), (folder, name)


def test_the_solver_hash_is_taken_by_folder():
    """The hash's inputs are every source file of scene/, dem/, specimen/
    and errors.py, found by walking those folders: no marker line in any
    file decides it."""
    walked = sorted(p.relative_to(PACKAGE).as_posix() for item in ("scene", "dem", "specimen")
                    for p in (PACKAGE / item).rglob("*")
                    if p.suffix in (".py", ".yaml") and "__pycache__" not in p.parts) + ["errors.py"]
    assert sources.simulation_sources() == sorted(walked)
    assert not any(b"ANALYSIS_ONLY" in p.read_bytes() for p in PACKAGE.rglob("*") if p.suffix in (".py", ".yaml"))


def test_a_new_module_joins_the_hash_of_its_folder(tmp_path, monkeypatch):
    """A copy of the package: a module added to specimen/ changes the
    hash; one added to analysis/ does not."""
    copy = tmp_path / "masonrydem"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    probe = ("import importlib, sys; sys.path.insert(0, sys.argv[1]); "
             "from masonrydem import sources; print(sources.source_hash())")

    def hash_of():
        return subprocess.run([sys.executable, "-c", probe, str(tmp_path)], capture_output=True, text=True,
                              check=True).stdout.strip()
    before = hash_of()
    (copy / "analysis" / "extra.py").write_text("X = 1\n")
    assert hash_of() == before
    (copy / "specimen" / "extra.py").write_text("X = 1\n")
    assert hash_of() != before


def test_the_sampling_code_holds_nothing_of_the_solver():
    """The sample rules' scripts draw through Study.draw and
    Study.pick_freeze (study.file), which read the scene (scene/) and
    nothing of the solver: no module of dem/ or specimen/ is in their
    fingerprints, which are therefore not the solver's hash's; the collect
    rule's is."""
    for script in ("sample.py", "sobol_check_sample.py"):
        sample = script_modules(ROOT / "workflow" / "scripts" / script)
        assert {"study.file", "study.sampling", "scene.typed"} <= sample, sample
        assert not any(simulation_module(m) for m in sample if m), sample
    collect = script_modules(ROOT / "workflow" / "scripts" / "collect.py")
    assert "dem.kernels.step" in collect and "specimen.row" in collect
    assert len(code_fingerprint(ROOT / "workflow" / "scripts" / "sample.py")) == 16


# --- a study of other names ------------------------------------------------------------
OTHER = {
    "name": "other_names",
    "scene": "config/scenes/willis.yaml",
    "samples": 12,
    "seed": 5,
    "variables": {
        "bond": {"setting": "materials.joints.ft", "distribution": "lognormal", "mean": "0.35 MPa", "cov": 0.3},
        "mor": {"setting": "materials.units.ft", "distribution": "normal", "mean": "4 MPa", "cov": 0.15},
        "E_unit": {"setting": "materials.units.E", "distribution": "lognormal", "mean": "12 GPa", "cov": 0.2},
    },
    "correlations": [{"between": ["mor", "E_unit"], "rho": 0.4}],
    "variants": {"per_wall": {"draw": "wallette"}},
    "rules": {"materials.joints.GI_per_ft": "0.03 mm", "loading.bending.rate": "2.0e-4 mm",
              "loading.bending.ramp_steps": 500, "numerics.cells": [2, 1, 1]},
    "sweep": {"setting": "loading.precompression.pressure", "name": "p", "levels": ["0 MPa", "0.1 MPa", "0.3 MPa"]},
    "regression": {"features": ["bond", "mor", "p"]},
}


@pytest.fixture(scope="module")
def other(tmp_path_factory):
    path = tmp_path_factory.mktemp("study") / "other.yaml"
    path.write_text(yaml.safe_dump(OTHER))
    return load_study(str(path))


def test_a_study_of_other_names_runs_through_the_row(other, tmp_path):
    """Its samples as the sample rule writes them; a run of one (the command
    line, as a workflow job runs it) reports bond_mpa, mor_mpa and
    E_unit_mpa, the sample's values (the mean over the wallette's joints or
    units of the value each holds, so to a digit); a sample the scene
    refuses is recorded as an error row with its message and its inputs,
    and the command exits 0 with --exit-zero (nothing crashes, nothing is
    lost)."""
    assert other.regression_variant == "per_wall" and other.columns()["p"] == "p_mpa"
    recs = other.draw("per_wall").records()
    bad = dict(recs[1], E_unit=5.0e12)         # beyond any plausible brick: the scene refuses it
    bad["settings"] = dict(bad["settings"], **{"materials.units.E": 5.0e12})
    samples = tmp_path / "samples.json"
    write_json(samples, [recs[0], bad])
    for n in (0, 1):
        out = tmp_path / f"s{n}"
        code = cli.main(["run", other.scene, "--samples", str(samples), "--sample", str(n), "--variant", "per_wall",
                         "--set", "loading.precompression.pressure=0.1e6", "--out", str(out), "--format", "json",
                         "--quiet", "--exit-zero"])
        assert code == 0
    good, refused = read_json(tmp_path / "s0" / "result.json"), read_json(tmp_path / "s1" / "result.json")
    assert good["ok"] and good["variant"] == "per_wall" and good["sample"] == 0
    assert (good["bond_mpa"], good["mor_mpa"], good["E_unit_mpa"]) == pytest.approx(
        (recs[0]["bond"] / 1e6, recs[0]["mor"] / 1e6, recs[0]["E_unit"] / 1e6), rel=1e-15)
    assert not {"f_tj_mpa", "f_tu_mpa", "E_b_mpa", "phi_j_deg"} & set(good)
    assert refused["status"] == "error" and not refused["ok"] and "materials.units.E" in refused["message"]
    assert refused["E_unit_mpa"] == 5.0e6 and refused["bond_mpa"] == recs[1]["bond"] / 1e6


def test_a_study_of_other_names_through_the_regression_and_predict(other):
    """The study's runs at its three levels, their strengths a known law of
    its inputs (the independent reason: the fit must find it), through the
    regression of its terms and its columns, and predict by its names."""
    cols = other.columns()
    rows = []
    for r in other.draw("per_wall").records():
        for p in (0.0, 0.1, 0.3):
            bond, mor = r["bond"] / 1e6, r["mor"] / 1e6
            rows.append({"variant": "per_wall", "sample": r["sample"], "ok": True, cols["p"]: p,
                         cols["bond"]: bond, cols["mor"]: mor, cols["E_unit"]: r["E_unit"] / 1e6,
                         "failure_mode": "joint", "strength_mpa": 0.1 + 4.0 * bond + 2.0 * p + 0.01 * mor})
    runs = pd.DataFrame(rows)
    fits, eq_rows, _ = E.prediction_equations(runs, other.features, cols)
    eq = fits["joint"][0]
    assert eq["coef"]["bond"] == pytest.approx(4.0, rel=0.01) and eq["coef"]["p"] == pytest.approx(2.0, rel=0.01)
    p = predict.build(fits, runs, build_scene(other.scene), "synthetic", cols, other.units, other.regression_variant,
                      {v.name: v.setting for v in other.variables})
    x = dict(bond="0.35 MPa", mor="4 N/mm^2", p="0.1 MPa")
    got = predict.predict(p, **x)
    assert got.strength_mpa == pytest.approx(0.1 + 4.0 * 0.35 + 2.0 * 0.1 + 0.01 * 4.0, rel=1e-3)
    assert got.inputs == dict(bond=0.35, mor=4.0, p=0.1) and p["variant"] == "per_wall"
    spec = plan.spec(other)
    assert spec["level_column"] == "p_mpa" and spec["regression_variant"] == "per_wall" and spec["precompression"]


def test_no_code_keys_on_the_willis_studys_names():
    """No string in the package's code (docstrings aside, where the Willis
    study is an example) is a variable, variant, term or column of the
    Willis study file: no code looks a study's data up by those names.
    The precompression's column, sigma_v_mpa, is the scene's own (the
    formulation's sigma_v, which every bending run reports whatever a study
    calls its sweep); the Willis study names its sweep after it."""
    import ast
    willis = load_study(str(ROOT / "config" / "studies" / "willis.yaml"))
    names = {v.name for v in willis.variables} | set(willis.variants) | set(willis.features)
    names |= {willis.column(v.name) for v in willis.variables}
    found = []
    for path in PACKAGE.rglob("*.py"):
        tree = ast.parse(path.read_text())
        docs = {id(n.body[0].value) for n in ast.walk(tree)
                if isinstance(n, (ast.Module, ast.FunctionDef, ast.ClassDef)) and n.body
                and isinstance(n.body[0], ast.Expr) and isinstance(n.body[0].value, ast.Constant)}
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
                found += [f"{path.relative_to(PACKAGE)}:{node.lineno} {n!r}" for n in names if n == node.value]
    assert not found, found


def test_snakemake_keeps_its_records_where_the_workflow_reads_them(tmp_path):
    """Snakemake's record store (pipeline/snakemake_state.py): a one-rule
    workflow run in a folder leaves the record of its output, a long path
    included (cut into names of the file system's length), where
    record_path says; the record names its rule.  Fails when another
    Snakemake lays its records out otherwise."""
    from masonrydem.pipeline.snakemake_state import read_record, record_path
    import hashlib
    long = "out/" + "/".join(hashlib.sha256(str(k).encode()).hexdigest() for k in range(5)) + "/a.txt"  # 334 letters
    (tmp_path / "Snakefile").write_text(
        f'rule all:\n    input: "{long}", "out/short.txt"\n\n'
        'rule make:\n    output: "out/{name}.txt"\n    shell: "echo made > {output}"\n')
    exe = Path(sys.executable).with_name("snakemake")
    r = subprocess.run([str(exe), "--cores", "1", "--quiet", "all"], cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    for out in (long, "out/short.txt"):
        where = tmp_path / record_path(out)
        assert where.is_file(), f"no record at {where}: Snakemake's record store is laid out otherwise"
        record = read_record(out, tmp_path / ".snakemake" / "metadata")
        assert record["rule"] == "make"
    assert len(record_path(long).parts) > 3       # the long name was cut into folders


# --- the scene as plain data ---------------------------------------------------------------
def test_reading_every_scene_and_study_file_loads_no_compiler():
    """Every committed scene built into a typed Scene and every committed
    study file loaded, its samples drawn, and `masonrydem check` of one,
    in a fresh interpreter: numba is never imported (nor the solver)."""
    code = """
import sys
from pathlib import Path
from masonrydem.scene import build_scene
from masonrydem.study import load_study
from masonrydem import cli
scenes = sorted(Path("config/scenes").glob("*.yaml"))
studies = [p for p in sorted(Path("config/studies").rglob("*.yaml")) if not p.stem.endswith("_workflow")]
for p in scenes:
    build_scene(str(p))
for p in studies:
    study = load_study(str(p))
    for variant in study.variants:
        study.draw(variant).records()
cli.main(["check", "config/studies/willis.yaml"])
print(len(scenes), len(studies), "numba" in sys.modules, any(m.startswith("masonrydem.dem") for m in sys.modules))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.split()[-4:] == ["9", "10", "False", "False"], out.stdout[-2000:]


def test_the_study_draws_its_samples_by_its_variants():
    """Study.draw: the other study's per-wallette variant as the sampling
    draws it (its Latin Hypercube: one value in each of the n strata of
    every variable), a per-item and a field variant of the same study with
    one value per unit and joint of its wallette, the same draw for other
    levels, another for another seed (its draw key likewise), and an
    unknown variant refused with the study's variants named."""
    from dataclasses import replace

    from masonrydem.errors import InputError
    from masonrydem.study.file import load_study, with_levels
    study = load_study(str(ROOT / "config" / "studies" / "willis.yaml"))
    other = replace(study, samples=6, variants={"one": {"draw": "wallette", "correlation_length": None},
                                               "each": {"draw": "items", "correlation_length": None},
                                               "fields": {"draw": "field", "correlation_length": 0.3}})
    wall = other.draw("one")
    for v in other.variables:
        u = v.frozen().cdf(wall.table[v.name].to_numpy())
        assert sorted(np.floor(u * 6).astype(int)) == list(range(6)), v.name
    items = other.items()
    for variant in ("each", "fields"):
        rec = other.draw(variant).records()[0]
        for v in other.variables:
            assert len(rec[v.name]) == len(items[v.per]) and v.per in ("unit", "joint"), (variant, v.name)
    again = with_levels(other, ["0 MPa", "0.3 MPa"], "levels")
    assert again.draw("one").records() == wall.records() and again.draw_key() == other.draw_key()
    reseeded = replace(other, seed=other.seed + 1)
    assert reseeded.draw("one").records() != wall.records() and reseeded.draw_key() != other.draw_key()
    with pytest.raises(InputError, match="no variant 'two'; its variants: one, each, fields"):
        other.draw("two")


def test_samples_are_drawn_by_the_study_alone():
    """No code outside study/ draws samples or builds sample records itself
    (the workflow, tools/ and benchmarks/ call Study.draw and
    Study.pick_freeze): none imports or calls the sampling's draws, the
    pick-freeze design or settings.record by name."""
    import ast
    names = {"wallette_samples", "study_samples", "item_samples", "field_samples", "lhs", "pick_freeze", "record"}
    files = [p for folder in ("src/masonrydem", "workflow", "tools", "benchmarks") for p in (ROOT / folder).rglob("*.py")
             if "study" not in p.relative_to(ROOT).parts[:3]]
    found = []
    for p in files:
        for node in ast.walk(ast.parse(p.read_text())):
            used = {a.name for a in node.names} if isinstance(node, ast.ImportFrom) and "study" in (node.module or "") \
                else {node.id} - {"record"} if isinstance(node, ast.Name) else set()     # 'record': a common name
            found += [f"{p.relative_to(ROOT)}:{node.lineno} {n}" for n in used & names]
    assert not found, found
