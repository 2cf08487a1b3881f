"""The Snakemake workflow: the smoke configuration runs the whole DAG end to
end; the full study plans 2 x 100 x 5 simulations."""
import json
import os
import re
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
import yaml

SNAKEMAKE = [sys.executable, "-m", "snakemake"]


@pytest.fixture(scope="module")
def smoke(tmp_path_factory):
    root = tmp_path_factory.mktemp("smoke") / "results"
    r = subprocess.run(SNAKEMAKE + ["all", "accuracy", "modelform", "--cores", "2",
                                    "--configfile", "config/smoke.yaml",
                                    "--config", f"results={root}", "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return root


def test_the_sobol_check_runs_its_pick_freeze_design(smoke):
    """config/smoke.yaml's check: 4 base points x (4 inputs + 2) = 24 runs at
    its level, each base row A, A with input i from B (i = 1..4), B, in the
    copula's independent inputs.  In the runs' own recorded inputs (f_tj,
    f_tu, phi_j, E_b; E_b correlated with f_tu, which comes first), a mixed
    run shares every input but the i-th with A, and E_b too where f_tu is
    mixed; its i-th input is B's, but for E_b, whose value also depends on
    A's f_tu.  One row per input in the check's table."""
    runs = pd.read_parquet(smoke / "sobol_check" / "runs.parquet")
    assert len(runs) == 24 and runs["sample"].tolist() == list(range(24)) and set(runs.sigma_v_mpa) == {0.5}
    x = runs[["f_tj_mpa", "f_tu_mpa", "phi_j_deg", "E_b_mpa"]].to_numpy().reshape(4, 6, 4)
    for i, moved in ((0, [0]), (1, [1, 3]), (2, [2]), (3, [3])):
        assert np.array_equal(np.delete(x[:, 1 + i], moved, axis=1), np.delete(x[:, 0], moved, axis=1)), i
        assert not np.any(x[:, 1 + i, moved] == x[:, 0, moved]), i
        if i != 3:
            assert np.array_equal(x[:, 1 + i, i], x[:, 5, i]), i
    check = pd.read_csv(smoke / "sobol_check" / "check.csv")
    assert check["input"].tolist() == ["f_tj_mpa", "f_tu_mpa", "phi_j_deg", "E_b_mpa"]
    assert "24 runs of the solver" in (smoke / "report" / "sobol_check.rst").read_text()


def test_smoke_study_outputs(smoke):
    """2 variants x 8 samples x 2 levels = 32 rows, one per simulation, with
    ids, inputs, outputs and status; statistics count every run."""
    runs = pd.read_parquet(smoke / "study" / "runs.parquet")
    assert len(runs) == 32
    assert set(runs.variant) == {"nonspatial", "spatial"} and set(runs.sigma_v_mpa) == {0.0, 0.5}
    assert runs.groupby(["variant", "sigma_v_mpa"]).size().tolist() == [8, 8, 8, 8]
    for col in ("sample", "f_tj_mpa", "f_tu_mpa", "phi_j_deg", "E_b_mpa", "P_max_kN", "strength_mpa",
                "failure_mode", "status", "ok", "steps", "wall_time_s"):
        assert col in runs.columns
    st = pd.read_csv(smoke / "study" / "statistics.csv")
    alls = st[st["mode"] == "all"]
    assert (alls["count"] + alls["excluded"]).tolist() == [8, 8, 8, 8]
    curves = pd.read_parquet(smoke / "study" / "curves.parquet")
    assert set(curves.variant) == {"nonspatial", "spatial"}
    # each run's curve thinned to study.curve_points (plus its peak), the peak
    # of its own curve kept
    per_run = curves.groupby(["variant", "sigma_v_mpa", "sample"]).load_kN
    assert per_run.size().max() <= yaml.safe_load(open("config/config.yaml"))["study"]["curve_points"] + 1
    paths = list((smoke / "study" / "runs").glob("*/sigma_v*/s*/curve.json"))
    assert len(paths) == 32
    for path in paths:
        variant, sv, sample = path.parts[-4], float(path.parts[-3][len("sigma_v"):]), int(path.parts[-2][1:])
        raw = json.loads(path.read_text())
        assert per_run.max()[(variant, sv, sample)] == np.float32(max(raw["load_kN"])), path
    # same samples at every level: the inputs of a sample do not depend on sigma_v
    ns = runs[runs.variant == "nonspatial"].pivot(index="sample", columns="sigma_v_mpa", values="f_tj_mpa")
    assert (ns[0.0] == ns[0.5]).all()
    # 3-D pictures per variant and mode; a pictured run is run again and must
    # repeat its recorded P_max exactly (the script refuses otherwise)
    for v in ("nonspatial", "spatial"):
        for m in ("joint", "brick"):
            assert (smoke / "study" / "pictures" / f"{v}_{m}.png").stat().st_size > 0
    assert "repeated exactly" in (smoke / "report" / "study_pictures.rst").read_text()


def test_smoke_prediction_equations(smoke):
    """The written tables say what their equations do: the smoke's
    non-spatial runs (8 samples x 2 levels) fit at least one mode's
    equation; each fitted equation's MAPE, recomputed here from its
    written coefficients on its mode's runs, is the one it reports (to the
    CSV's 6 digits); so is the lower-of-two predictor's over every ok
    non-spatial run; and the design table's prediction at 0 MPa is the
    lower of the written equations at the mean strengths, its band
    sqrt(property_sd^2 + residual_sd^2)."""
    from masonrydem.analysis import equations as E
    from masonrydem.study.file import load_study
    study = load_study("config/studies/willis.yaml")
    columns = study.columns()
    eq = pd.read_csv(smoke / "study" / "equations.csv").set_index("mode")
    runs = pd.read_parquet(smoke / "study" / "runs.parquet")
    ns = runs[runs.ok & (runs.variant == "nonspatial")]
    fitted = eq[eq.alpha.notna()]
    assert len(fitted) >= 1
    equations = {m: dict(intercept=r.intercept, coef={k: r[k] for k in study.features}) for m, r in fitted.iterrows()}
    for mode, e in equations.items():
        g = ns[ns.failure_mode == mode]
        predicted = E.predict(e, E.inputs_of(g, columns))
        assert E.mape(g.strength_mpa, predicted) == pytest.approx(eq.loc[mode, "mape_pct"], rel=1e-4), mode
    joint, brick = equations.get("joint", equations.get("brick")), equations.get("brick", equations.get("joint"))
    low, _ = E.lower_of_two(joint, brick, E.inputs_of(ns, columns))
    assert eq.loc["lower of two", "n"] == len(ns)
    assert E.mape(ns.strength_mpa, low) == pytest.approx(eq.loc["lower of two", "mape_pct"], rel=1e-4)
    design = pd.read_csv(smoke / "study" / "design_comparison.csv").set_index("sigma_v_mpa")
    means = study.means()
    at_mean, _ = E.lower_of_two(joint, brick, dict(f_tu=[means["f_tu"]], f_tj=[means["f_tj"]], sigma_v=[0.0]))
    assert design.loc[0.0, "prediction"] == pytest.approx(at_mean[0], rel=1e-4)
    np.testing.assert_allclose(design.band_sd, np.hypot(design.property_sd, eq.loc["lower of two", "residual_sd_mpa"]),
                               rtol=1e-4)


def test_smoke_validation_outputs(smoke):
    for name in ("summary.csv", "load_displacement.png", "model_numbering.png", "damage_reference_sv0.0.png"):
        assert (smoke / "validation" / name).stat().st_size > 0


def test_smoke_accuracy_outputs(smoke):
    """The accuracy study's tables and figures, and every generated report
    caption filled in (no template field left)."""
    for name in ("runs.csv", "convergence.csv", "choice.csv", "pareto.png", "scaling.csv", "scaling.png",
                 "subsample.csv", "subsample.png"):
        assert (smoke / "accuracy" / name).stat().st_size > 0
    captions = list((smoke / "report").glob("*.rst"))
    assert len(captions) >= 15
    for c in captions:
        text = c.read_text()
        # a str.format field ({name} or {name:spec}) left unfilled; a brace
        # of the landing page's own CSS ({align-items:...}) is not one
        assert not re.search(r"\{[A-Za-z_]\w*(?:[:!][^{}\n]*)?\}", text), c.name
        assert not re.search(r"\bnan\b", text, re.IGNORECASE), c.name


def test_smoke_stability_and_reduced_outputs(smoke):
    """The hard-cases table (a run and its half-rate rerun) and the reduced
    models' table: every model of the main config on the smoke case (their
    rules on constructed rows: tests/test_tables.py)."""
    hard = pd.read_csv(smoke / "stability" / "hard_cases.csv")
    assert set(hard.run) == {"reference", "reference_half_rate"}
    red = pd.read_csv(smoke / "reduced" / "summary.csv")
    assert set(red.model) == {"full", "pc", "elastic", "rigid"} and set(red.case) == {"ref_sv0"}


def test_smoke_specimens(smoke):
    """Both further tests run from the workflow, each in its row; the
    triplet's peak lies at or below the plastic limit c + sigma tan(phi)
    of its joints (softening and a non-uniform shear stress bring it
    below; tests/test_specimens.py measures how close) and its figure and
    caption are written."""
    t = pd.read_csv(smoke / "specimens" / "summary.csv")
    assert sorted(t.test) == ["tension", "triplet"] and t.status.isin(["load_drop", "displacement_limit"]).all()
    trip = t[t.test == "triplet"].iloc[0]
    assert -0.03 < trip.peak_error <= 1e-3
    assert (smoke / "specimens" / "response.png").stat().st_size > 0
    assert "c + sigma tan phi" in (smoke / "report" / "specimens.rst").read_text()


def test_report_opens_on_the_study(smoke, tmp_path):
    """The README's report command builds the report, the accuracy study's
    summaries included, and its landing page (workflow/report/workflow.rst,
    filled by the rule statistics) says what was run and holds the study's
    key table, one row per variant and level."""
    import zipfile
    out = tmp_path / "report.zip"
    r = subprocess.run(SNAKEMAKE + ["--report", str(out), "all", "accuracy", "modelform",
                                    "--configfile", "config/smoke.yaml",
                                    "--config", f"results={smoke}"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    names = zipfile.ZipFile(out).namelist()
    # the tables as pages the browser shows (src/masonrydem/report/tables.py)
    assert any(n.endswith("accuracy_choice.html") for n in names) and any(n.endswith("/statistics.html") for n in names)
    landing = (smoke / "report" / "workflow.rst").read_text()
    assert "32 simulations" in landing and "2 variants x 8 Latin Hypercube samples" in landing
    rows = [x.split() for x in landing.splitlines() if re.match(r"(non)?spatial +[0-9.]+ +[0-9.]+ ", x)]
    assert len(rows) == 4, landing
    # its numbers are statistics.csv's (mode 'all'), as rounded on the page
    st = pd.read_csv(smoke / "study" / "statistics.csv")
    for variant, sv, mean, strength, cov, brick, count in rows:
        s = st[(st.variant == variant) & (st.sigma_v_mpa == float(sv)) & (st["mode"] == "all")].iloc[0]
        assert (mean, strength, cov, brick, int(count)) == (f"{s.P_max_mean_kN:.2f}", f"{s.strength_mean_mpa:.3f}",
                                                           f"{s.P_max_cov:.3f}", f"{100 * s.brick_share:.0f}",
                                                           s["count"]), (variant, sv)


def test_rerun_does_nothing(smoke):
    """Nothing to do after a complete run (outputs are up to date)."""
    r = subprocess.run(SNAKEMAKE + ["-n", "--configfile", "config/smoke.yaml", "--config", f"results={smoke}"],
                       capture_output=True, text=True)
    assert r.returncode == 0 and "Nothing to be done" in r.stdout + r.stderr


def test_a_setting_sampling_does_not_read_reruns_no_simulation(smoke, tmp_path):
    """Changing how the curves are collected replans the collection and what
    follows it, never the sampling or the simulations (a params change of
    the sample rule would redraw the samples and rerun every simulation)."""
    extra = tmp_path / "curve_points.yaml"
    extra.write_text(yaml.safe_dump({"study": {"curve_points": 77}}))
    r = subprocess.run(SNAKEMAKE + ["-n", "--configfile", "config/smoke.yaml", str(extra),
                                    "--config", f"results={smoke}"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    planned = planned_jobs(r.stdout)
    assert "collect" in planned and not set(planned) & {"sample", "simulate"}, r.stdout[-2000:]


SWEEP_STUDY = """
name: joints
scene: config/scenes/willis.yaml
samples: 8
seed: 3
variables:
  f_tj: {setting: materials.joints.ft, per: joint, distribution: lognormal, mean: 0.30 MPa, cov: 0.40}
  f_tu: {setting: materials.units.ft, per: unit, distribution: lognormal, mean: 3.75 MPa, cov: 0.25}
variants:
  nonspatial: {draw: wallette}
rules:
  materials.units.Gf_rule: {coefficient: 0.04, exponent: 0.7}
  materials.joints.GI_per_ft: 0.03 mm
  materials.joints.Em_ratio: 0.1
sweep: {setting: geometry.joint_thickness, name: t, levels: [8 mm, 14 mm]}
regression:
  features: [f_tu, f_tj, t, f_tj*t]
"""


def test_a_study_that_sweeps_another_setting(tmp_path):
    """A study file that sweeps the joint thickness (not the precompression)
    with terms of its own runs end to end at the smoke's numerics: the runs'
    folders are named by the sweep (t8.0), the runs table has the column
    t_mm from those folders, the statistics are per t_mm, the equations
    have the study's terms and the predictor takes t in mm; the design
    comparison, which needs the precompression, says why it is absent."""
    (tmp_path / "joints.yaml").write_text(SWEEP_STUDY)
    (tmp_path / "workflow.yaml").write_text(yaml.safe_dump(dict(
        results=str(tmp_path / "results"), study=dict(file=str(tmp_path / "joints.yaml"), levels=["8 mm", "14 mm"],
                                                      paper=None), sobol_check=None)))
    r = subprocess.run(SNAKEMAKE + ["study", "--cores", "2", "--configfile", "config/smoke.yaml",
                                    str(tmp_path / "workflow.yaml"), "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    out = tmp_path / "results" / "study"
    assert sorted(p.name for p in (out / "runs" / "nonspatial").iterdir()) == ["t14.0", "t8.0"]
    runs = pd.read_parquet(out / "runs.parquet")
    assert len(runs) == 16 and runs.groupby("t_mm").size().to_dict() == {8.0: 8, 14.0: 8}
    assert set(runs.sigma_v_mpa) == {0.0}           # the scene's precompression, not swept
    st = pd.read_csv(out / "statistics.csv")
    assert set(st.t_mm) == {8.0, 14.0} and "sigma_v_mpa" not in st
    for t, g in runs[runs.ok].groupby("t_mm"):
        row = st[(st.t_mm == t) & (st["mode"] == "all")].iloc[0]
        assert row["count"] == len(g) and row.P_max_mean_kN == pytest.approx(g.P_max_kN.mean(), rel=1e-3)
    eq = pd.read_csv(out / "equations.csv")
    assert {"f_tu", "f_tj", "t", "f_tj*t"} <= set(eq.columns)
    predictor = json.loads((out / "predictor.json").read_text())
    assert predictor["inputs"]["t"] == dict(unit="m", shown="mm", column="t_mm", setting="geometry.joint_thickness")
    assert predictor["fitted_range"]["t"] == [8.0, 14.0]
    assert "sweeps geometry.joint_thickness" in (out / "design_comparison.csv").read_text()
    assert sorted(pd.read_csv(out / "characteristic.csv").t_mm) == [8.0, 14.0]
    assert "levels of t (8, 14 mm)" in (tmp_path / "results" / "report" / "workflow.rst").read_text()


@pytest.mark.parametrize("runs", [50, 1])
def test_full_study_plans_1000_simulations_in_batches(tmp_path, runs):
    """The study's 1000 runs in jobs of config batch.runs: at 50 20 jobs
    (2 variants x 5 levels x 2), at 1 a job each (1000 jobs), their
    outputs every run's row and curve once."""
    r = subprocess.run(SNAKEMAKE + ["-n", "--config", f"results={tmp_path}", f"batch={{runs: {runs}}}"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    # the default profile is found beside the Snakefile
    assert "Using workflow specific profile profiles/default" in r.stdout + r.stderr
    jobs = re.findall(r"rule simulate_\d+:\n(?:\s+input:.*\n)?\s+output: (.*)\n", r.stdout)
    assert len(jobs) == 1000 // runs and planned_jobs(r.stdout)["simulate"] == 1000
    results = [f for job in jobs for f in job.split(", ") if f.endswith("result.json")]
    assert len(set(results)) == 1000 and all(len([f for f in job.split(", ") if f.endswith("result.json")]) == runs
                                             for job in jobs)


def test_full_study_plans_on_slurm(tmp_path):
    """The cluster profile (snakemake-executor-plugin-slurm, a batch of the
    study's simulations a cluster job) plans the full DAG (dry run), with
    the partition from the environment, the profile's own resources (a
    --default-resources on the command line would replace them) and a
    batch's runtime, a minute a run.  Run for real: tests/test_cluster.py."""
    env = dict(os.environ, MASONRYDEM_SLURM_PARTITION="test")
    r = subprocess.run(SNAKEMAKE + ["-n", "--profile", "profiles/slurm", "--config", f"results={tmp_path}"],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr[-2000:]
    assert planned_jobs(r.stdout)["simulate"] == 1000
    sim = r.stdout[r.stdout.index("rule simulate_0:"):]
    resources = sim[sim.index("resources:"):].splitlines()[0]
    assert "slurm_partition=test" in resources and "runtime=100" in resources and "mem_mb=2000" in resources


def test_a_simulation_that_raises_is_recorded(tmp_path):
    """Nothing lost: a sample the scene refuses (f_tj < 0) still gives its
    job's row, with status 'error', ok False and the refusal naming the
    field, the sample's inputs, and an empty curve (the statistics exclude
    and count such rows: tests/test_analysis.py)."""
    from dataclasses import replace

    from masonrydem.pipeline import plan
    from masonrydem.specimen.row import write_json
    smoke = yaml.safe_load(open("config/smoke.yaml"))["study"]
    drawn = plan.study({"study": {"file": "config/studies/willis.yaml", **smoke}}).draw("nonspatial")
    nonspatial = drawn.table.copy()          # the study's draw, its first sample's bond made negative
    nonspatial.loc[nonspatial["sample"] == 0, "f_tj"] = -1e5
    root = tmp_path / "results"
    (root / "study").mkdir(parents=True)
    write_json(root / "study" / "samples_nonspatial.json", replace(drawn, table=nonspatial).records())
    target = root / "study" / "runs" / "nonspatial" / "sigma_v0.0" / "s0" / "result.json"
    r = subprocess.run(SNAKEMAKE + [str(target), "--cores", "1", "--allowed-rules", "simulate_0", "--configfile",
                                    "config/smoke.yaml", "--config", f"results={root}"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    row = json.loads(target.read_text())
    assert row["status"] == "error" and not row["ok"] and "materials.joints.ft" in row["message"]
    assert (row["variant"], row["sample"], row["sigma_v_mpa"]) == ("nonspatial", 0, 0.0)
    s0 = nonspatial.iloc[0]
    assert (row["f_tj_mpa"], row["f_tu_mpa"], row["E_b_mpa"], row["phi_j_deg"]) == (-0.1, s0.f_tu / 1e6, s0.E_b / 1e6,
                                                                                      s0.phi_j)
    assert json.loads(target.with_name("curve.json").read_text())["load_kN"] == []
    # and its batch went on: the job's other samples ran
    others = [json.loads(p.read_text()) for p in target.parent.parent.glob("s*/result.json") if p != target]
    assert len(others) == smoke["samples"] - 1 and all(o["ok"] for o in others)


def test_lint_finds_nothing(tmp_path):
    """`snakemake --lint` is clean: no path composed with '+', no absolute
    path, every rule that runs a script with a log and a conda environment
    (workflow/envs/masonrydem.yaml)."""
    r = subprocess.run(SNAKEMAKE + ["--lint", "--config", f"results={tmp_path}"], capture_output=True, text=True)
    out = r.stdout + r.stderr
    assert r.returncode == 0 and "Congratulations, your workflow is in a good condition!" in out, out[-3000:]
    assert not [x for x in out.splitlines() if x.startswith("Lints for ")], out[-3000:]


def test_a_run_that_raises_is_recorded_as_the_workflow_runs_it(tmp_path, monkeypatch):
    """Nothing lost in the rules that run the command line (validation,
    hard cases, reduced models, specimens, accuracy: `masonrydem.cli run
    ... --exit-zero`): a run that raises (here the simulation itself,
    replaced by one that raises) writes its row with status 'error' and the
    exception as its message, and an empty curve, and the job ends
    normally (exit 0: its row is written)."""
    import masonrydem.specimen.protocol
    from masonrydem import cli

    def boom(scene, progress=True):
        raise RuntimeError("a failure inside the run")

    monkeypatch.setattr(masonrydem.specimen.protocol, "simulate", boom)
    out = tmp_path / "runs" / "joint_sv0" / "default"
    code = cli.main(["run", "config/scenes/willis.yaml", "--set", "geometry.courses=2", "--set",
                     "name=accuracy:joint_sv0:default", "--out", str(out), "--exit-zero", "--quiet"])
    assert code == 0
    row = pd.read_parquet(out / "result.parquet").iloc[0]
    assert row["status"] == "error" and not row["ok"]
    assert row["message"] == "RuntimeError: a failure inside the run"
    assert row["scene"] == "accuracy:joint_sv0:default"
    assert pd.read_parquet(out / "curve.parquet").empty


def _planned(smoke, extra=(), env=None, targets=()):
    """The jobs a dry run over the completed smoke results plans: rule ->
    count; the study's batches (rules simulate_<k>, simulate_fine_<k>,
    simulate_sobol_<k>) as 'simulate', 'simulate_fine' and
    'simulate_sobol', counted in runs (their outputs)."""
    r = subprocess.run(SNAKEMAKE + [*targets, "-n", "--configfile", "config/smoke.yaml", *extra, "--config",
                                    f"results={smoke}"], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    return planned_jobs(r.stdout)


def planned_jobs(text):
    """planned's count from a dry run's output ``text``."""
    jobs = (re.fullmatch(r"(\w+)\s+(\d+)", x.strip()) for x in text.splitlines())
    out = {m[1]: int(m[2]) for m in jobs
           if m and m[1] != "total" and not re.fullmatch(r"simulate_(fine_|sobol_)?\d+", m[1])}
    for rule, outputs in re.findall(r"rule (simulate_(?:fine_|sobol_)?)\d+:\n(?:\s+input:.*\n)?\s+output: (.*)\n",
                                    text):
        out[rule[:-1]] = out.get(rule[:-1], 0) + outputs.count("result.json")
    return out


def _package_copy(tmp_path, module, line):
    """A copy of the package with ``line`` appended to ``module``, first on
    the path of the subprocess (the environment to pass)."""
    import shutil

    import masonrydem
    root = tmp_path / "pkg"
    shutil.copytree(os.path.dirname(masonrydem.__file__), root / "masonrydem",
                    ignore=shutil.ignore_patterns("__pycache__"))
    with open(root / "masonrydem" / module, "a") as f:
        f.write(f"\n{line}\n")
    return dict(os.environ, PYTHONPATH=str(root))


def test_a_solver_change_reruns_every_simulation(smoke, tmp_path):
    """A change to what a simulation computes (a statement in dem/laws.py,
    a module of the source hash) replans every simulation of the smoke: the
    32 study runs and the runs of every other stage, as many as the plan
    names (pipeline/plan.py); not the sampling."""
    from masonrydem.pipeline import plan
    smoke_config = yaml.safe_load(open("config/smoke.yaml"))
    planned = _planned(smoke, env=_package_copy(tmp_path, "dem/laws.py", "_CHANGED = 1"),
                       targets=["all", "accuracy", "modelform"])
    assert planned.get("simulate") == 32 and planned.get("validation_run") == 1, planned
    assert planned.get("hard_case_run") == 2 and planned.get("specimen_run") == 2, planned
    assert planned.get("accuracy_run") == len(plan.accuracy_runs(smoke_config)), planned
    assert planned.get("accuracy_check_run") == len(plan.reference_checks(smoke_config)), planned
    assert "sample" not in planned, planned
    assert planned.get("modelform_run") == len(plan.modelform_runs(smoke_config)) == 2, planned
    check = smoke_config["sobol_check"]
    assert planned.get("simulate_sobol") == check["base"] * (4 + 2) == 24, planned     # 4 inputs
    assert "sobol_check_sample" not in planned, planned


PER_RUN_RULES = {"simulate", "simulate_fine", "simulate_sobol", "sobol_check_sample", "accuracy_run",
                 "accuracy_check_run", "accuracy_scaling_run",
                 "modelform_run", "hard_case_run", "reduced_run", "specimen_run", "validation_run", "sample"}


def test_an_analysis_change_reruns_the_analysis_and_no_simulation(smoke, tmp_path):
    """A change to the analysis of results (analysis/statistics.py, outside
    the source hash) reruns the rules whose scripts may use it (their
    parameter 'code'), and no simulation, nor the sampling."""
    planned = _planned(smoke, env=_package_copy(tmp_path, "analysis/statistics.py", "_CHANGED = 1"))
    assert {"statistics", "figures", "regression", "collect"} <= set(planned), planned
    assert not set(planned) & PER_RUN_RULES, planned


def test_a_changed_figure_script_reruns_that_figure_alone(smoke, tmp_path):
    """A statement added to the figures' script (a copy of the workflow, run
    on the smoke results) plans the rule 'figures' and nothing else."""
    import shutil
    for name in ("Snakefile", "workflow", "profiles", "config"):
        (shutil.copytree if os.path.isdir(name) else shutil.copy)(name, tmp_path / name)
    with open(tmp_path / "workflow" / "scripts" / "figures.py", "a") as f:
        f.write("\n_CHANGED = 1\n")
    planned = _planned(smoke, ["-s", str(tmp_path / "Snakefile")])
    assert set(planned) - {"all"} == {"figures"}, planned


def _clone(smoke, root):
    """The smoke results as a clone has them: without what git leaves out
    (the single runs, the samples, states, logs: .gitignore), without
    Snakemake's records of them (another path), and with file times in
    reverse order, older than the workflow's files."""
    import shutil

    def left_out(folder, names):
        run_folders = {"runs", "subsample", "scaling", "state", "logs", "benchmarks"}
        return [n for n in names if (n in run_folders and not folder.endswith("validation"))
                or n == "state" or n.startswith("samples") and n.endswith(".json") or n.endswith(".vtm")]
    shutil.copytree(smoke, root, ignore=left_out)
    files = sorted((p for p in root.rglob("*") if p.is_file()), key=lambda p: p.stat().st_mtime)
    for i, p in enumerate(reversed(files)):
        os.utime(p, (1.6e9 + i, 1.6e9 + i))
    return root


def test_a_clone_plans_nothing_and_still_sees_a_change(smoke, tmp_path):
    """A clone of the results plans nothing: Snakemake's records, saved in
    provenance.json, are put back, and judge by checksum, not by file
    time.  On the clone, a solver change still plans every simulation of
    the smoke, and a numerics change every run it affects."""
    clone = _clone(smoke, tmp_path / "clone" / "results")
    assert (clone / "provenance.json").is_file() and not (clone / "study" / "runs").exists()
    assert _planned(clone) == {}
    planned = _planned(clone, env=_package_copy(tmp_path, "dem/laws.py", "_CHANGED = 1"))
    assert planned.get("simulate") == 32 and planned.get("validation_run") == 1, planned
    assert planned.get("hard_case_run") == 2 and planned.get("specimen_run") == 2, planned
    extra = tmp_path / "extra.yaml"
    extra.write_text(yaml.safe_dump({"numerics": yaml.safe_load(open("config/smoke.yaml"))["numerics"]
                                     + ["numerics.record_every=20"]}))
    planned = _planned(clone, [str(extra)])
    assert planned.get("simulate") == 32 and planned.get("validation_run") == 1, planned
    assert "specimen_run" not in planned, planned


def test_a_numerics_change_reruns_every_run_and_a_new_level_only_its_own(smoke, tmp_path):
    """The numerics are every run's overrides: changing them replans every
    simulation (study, validation, hard cases); a new precompression level
    plans its 16 study runs (2 variants x 8 samples), and no other study
    run."""
    extra = tmp_path / "extra.yaml"
    extra.write_text(yaml.safe_dump({"numerics": yaml.safe_load(open("config/smoke.yaml"))["numerics"]
                                     + ["numerics.record_every=20"]}))
    planned = _planned(smoke, [str(extra)])
    assert planned.get("simulate") == 32 and planned.get("validation_run") == 1, planned
    extra.write_text(yaml.safe_dump({"study": {"levels": ["0 MPa", "0.25 MPa", "0.5 MPa"]}}))
    planned = _planned(smoke, [str(extra)])
    assert planned.get("simulate") == 16 and "validation_run" not in planned, planned


def test_an_interrupted_run_resumes_with_what_is_missing(smoke, tmp_path):
    """Ctrl-C during the smoke study (4 batches of 8 runs, 2 at a time):
    Snakemake stops, the batches it finished stay; the same command again
    plans exactly the others (an interrupted batch's runs are removed, or,
    when Snakemake's scheduler took the Ctrl-C before the batch's error,
    kept and marked incomplete: Snakemake reruns incomplete outputs), and
    completes the study without touching the finished batches, every run
    as the uninterrupted smoke has it."""
    import signal
    import time
    root = tmp_path / "results"
    cmd = SNAKEMAKE + [f"{root}/study/runs.parquet", "--cores", "2", "--configfile", "config/smoke.yaml",
                       "--config", f"results={root}"]

    def finished():     # simulations with both outputs
        return sum((r.parent / "curve.json").exists() for r in root.glob("study/runs/*/sigma_v*/s*/result.json"))

    # Ctrl-C in a terminal interrupts the whole foreground process group:
    # Snakemake and the simulations it runs
    log = tmp_path / "interrupted.log"    # a file, not a pipe: Snakemake would block on a full pipe
    # (with Ctrl-C's default action: a shell that runs the suite in the
    # background, `make test &`, has its children ignore SIGINT)
    p = subprocess.Popen(cmd, stdout=open(log, "w"), stderr=subprocess.STDOUT, start_new_session=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.time() + 600
    # a batch done (in Snakemake's log) and another started
    while not ("(Rule: simulate_" in log.read_text() and finished() >= 9) and time.time() < deadline:
        time.sleep(0.1)

    def took_it():
        text = log.read_text()
        return p.poll() is not None or "Terminating processes on user request" in text or "SIGINT" in text
    # Ctrl-C, again only if nothing took it within 20 s: a SIGINT that lands
    # while Snakemake writes a log line is swallowed by its log handler
    # (snakemake/logging.py: `except (KeyboardInterrupt, SystemExit): pass`),
    # as a user in a terminal would find it
    for _ in range(10):
        os.killpg(p.pid, signal.SIGINT)
        t0 = time.time()
        while not took_it() and time.time() - t0 < 20.0:
            time.sleep(0.1)
        if took_it():
            break
    p.wait(timeout=300)
    text = log.read_text()
    batches = set(re.findall(r"^(simulate_\d+) +1$", text, re.M))
    logged = set(re.findall(r"Finished jobid: \d+ \(Rule: (simulate_\d+)\)", text))
    assert len(batches) == 4 and 1 <= len(logged) < 4, text[-3000:]
    kept = {p: p.stat().st_mtime_ns for p in root.glob("study/runs/*/sigma_v*/s*/*.json")}
    r = subprocess.run(cmd + ["-n"], capture_output=True, text=True)
    # a batch that finished is not planned again; one that ended its runs
    # as the Ctrl-C came may be in either set (its outputs whole, Snakemake
    # interrupted before it logged the batch finished), and is judged below
    # by its runs: kept whole or written again
    done = batches - set(re.findall(r"^(simulate_\d+) +1$", r.stdout, re.M))
    assert logged <= done and len(done) < 4, (logged, r.stdout[-2000:])
    assert subprocess.run(cmd, capture_output=True).returncode == 0
    # the finished batches' runs untouched (8 runs, a result and a curve
    # each), the others written again
    written = [p for p, t in kept.items() if p.stat().st_mtime_ns != t]
    assert len(kept) - len(written) == 16 * len(done), (len(kept), len(written), done)
    runs = pd.read_parquet(root / "study" / "runs.parquet").set_index(["variant", "sigma_v_mpa", "sample"])
    ref = pd.read_parquet(smoke / "study" / "runs.parquet").set_index(["variant", "sigma_v_mpa", "sample"])
    assert len(runs) == 32 and runs.P_max_kN.equals(ref.P_max_kN.loc[runs.index]) and runs.steps.equals(
        ref.steps.loc[runs.index])


def test_a_further_study_gets_a_report_page_that_states_its_numbers(tmp_path):
    """config further_studies: a study's tables (made up here, with numbers
    known in advance) become one page of the report (statistics, then
    equations), and its caption gives the means of its regression
    variant's runs at each level and its equations as written."""
    demo = tmp_path / "demo"
    (demo / "study").mkdir(parents=True)
    st = pd.DataFrame(dict(variant=["nonspatial"] * 2 + ["spatial"] * 2, sigma_v_mpa=[0.0, 0.5] * 2, mode="all",
                           count=10, P_max_mean_kN=[11.125, 15.5, 99.0, 99.0], P_max_cov=[0.21, 0.12, 0.5, 0.5],
                           strength_mean_mpa=[1.6, 2.2, 9.0, 9.0], brick_share=[0.1, 0.6, 0.0, 0.0], excluded=0))
    st.to_csv(demo / "study" / "statistics.csv", index=False)
    eq = pd.DataFrame(dict(mode=["joint", "brick", "lower of two"], n=[12, 8, 20],
                           equation=["sigma = 0.2 + 4.5 f_tj  (MPa)", "sigma = 0.5 + 0.5 f_tu  (MPa)",
                                     "min(joint, brick)"]))
    eq.to_csv(demo / "study" / "equations.csv", index=False)
    extra = tmp_path / "extra.yaml"
    extra.write_text(yaml.safe_dump({"further_studies": {"demo": {
        "title": "demo", "short": "demo", "results": str(demo), "workflow": "config/studies/nf_workflow.yaml"}}}))
    r = subprocess.run(SNAKEMAKE + [f"{tmp_path}/report/studies/demo.html", "--cores", "1", "--configfile",
                                    "config/config.yaml", str(extra), "--config", f"results={tmp_path}"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    page = (tmp_path / "report" / "studies" / "demo.html").read_text()
    caption = (tmp_path / "report" / "further_study_demo.rst").read_text()
    assert page.count("<table") == 2 and page.count("</html>") == 1 and page.count("</tr>") == len(st) + len(eq) + 2
    assert ("0 MPa: 11.12 kN (COV 0.21), 1.60 MPa, brick share 10%; 0.5 MPa: 15.50 kN (COV 0.12), 2.20 MPa, "
            "brick share 60%") in caption
    assert "99.00" not in caption          # the other variant's runs are not the regression variant's
    assert "sigma = 0.2 + 4.5 f_tj  (MPa)" in caption and "sigma = 0.5 + 0.5 f_tu  (MPa)" in caption


def test_the_sensitivity_rule_produces_the_indices_of_a_known_law(tmp_path):
    """The workflow's sensitivity rule (smoke config, the Willis study
    file) on runs whose strength is a known law of two inputs, 4 f_tj +
    0.5 f_tu (MPa), over 30 samples at two levels: a linear surrogate, and
    Sobol indices over the study's own distributions (f_tj lognormal, mean
    0.3 MPa, COV 0.4: variance 0.12^2; f_tu mean 3.75 MPa, COV 0.25:
    0.9375^2), S = 16 x 0.0144 : 0.25 x 0.8789 = 0.512 : 0.488; f_tu is
    correlated with E_b but comes first in the study file, so it carries
    the full index and E_b none; phi_j none."""
    from dataclasses import replace

    from masonrydem.study.file import load_study
    study = replace(load_study("config/studies/willis.yaml"), samples=30, seed=3)
    table = study.draw("nonspatial").table
    (tmp_path / "study").mkdir()
    cols = study.columns()
    runs = pd.DataFrame([{"variant": "nonspatial", "sample": r["sample"], "sigma_v_mpa": sv, "ok": True,
                          "failure_mode": "joint", "P_max_kN": 1.0,
                          **{cols[v.name]: r[v.name] / (1e6 if study.units[v.name] == "Pa" else 1.0)
                             for v in study.variables}}
                         for r in table.to_dict("records") for sv in (0.0, 0.5)])
    runs["strength_mpa"] = 4.0 * runs.f_tj_mpa + 0.5 * runs.f_tu_mpa
    runs.to_parquet(tmp_path / "study" / "runs.parquet")
    pd.DataFrame(dict(variant="nonspatial", sigma_v_mpa=[0.0, 0.5], mode="all", f_tj_mpa=0.0, f_tu_mpa=0.0,
                      phi_j_deg=0.0, E_b_mpa=0.0)).to_csv(tmp_path / "study" / "correlations.csv", index=False)
    out = tmp_path / "study" / "sensitivity.csv"
    r = subprocess.run(SNAKEMAKE + [str(out), "--allowed-rules", "sensitivity", "--cores", "1", "--configfile",
                                    "config/smoke.yaml", "--config", f"results={tmp_path}"], capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    t = pd.read_csv(out)
    t = t[t["mode"] == "all"]
    v_tj, v_tu = 16 * (0.4 * 0.3) ** 2, 0.25 * (0.25 * 3.75) ** 2
    for sv, g in t.groupby("sigma_v_mpa"):
        g = g.set_index("input")
        assert (g.surrogate == "gaussian process").all() and (g.cv_r2 > 0.999).all()
        for col, share in (("f_tj_mpa", v_tj / (v_tj + v_tu)), ("f_tu_mpa", v_tu / (v_tj + v_tu)),
                           ("phi_j_deg", 0.0), ("E_b_mpa", 0.0)):
            assert g.loc[col, "ST"] == pytest.approx(share, abs=0.01) and g.loc[col, "S1"] == pytest.approx(
                share, abs=0.01), (sv, col)


def test_the_workflow_refuses_a_bad_study_file_at_planning_as_check_does(tmp_path):
    """The workflow runs the study file's checks when it plans: a standard
    deviation without its unit stops it with exit 2, the key named and the
    message `masonrydem check` gives, no traceback, nothing run."""
    study = tmp_path / "study.yaml"
    study.write_text(open("config/studies/willis.yaml").read().replace("mean: 0.30 MPa, cov: 0.40",
                                                                        "mean: 0.30 MPa, sd: 0.12"))
    extra = tmp_path / "extra.yaml"
    extra.write_text(yaml.safe_dump({"study": {"file": str(study)}}))
    r = subprocess.run(SNAKEMAKE + ["-n", "--configfile", "config/smoke.yaml", str(extra), "--config",
                                    f"results={tmp_path / 'results'}"], capture_output=True, text=True)
    check = subprocess.run([sys.executable, "-m", "masonrydem.cli", "check", str(study)], capture_output=True,
                           text=True)
    assert r.returncode == 2 and check.returncode == 2
    message = check.stderr.strip().splitlines()[-1]
    assert message.startswith("masonrydem: invalid input: study.variables.f_tj.sd: 0.12 has no unit")
    assert message in r.stderr and "Traceback" not in r.stderr + r.stdout
    assert not (tmp_path / "results").exists()


# what the Willis study's words and numbers are: its name, its variants, its
# inputs and columns, its wallette's counts and size, its levels beyond the
# small study's
WILLIS_WORDS = ("willis", "nonspatial", "non-spatial", "spatial", "f_tj", "f_tu", "phi_j", "E_b", "sigma_v",
                "24 units", "38 joints", "100 runs", "1000 runs", "both variants", "230 x", "0.5 MPa", "0.15 MPa")


def test_a_small_studys_report_is_written_from_its_own_file(tmp_path):
    """The committed worked example (config/studies/waal.yaml: other
    variable names, one variant, no paper, levels up to 0.3 MPa): its
    report, built from its committed results by its own workflow config,
    has no dead link (docutils reports none) and none of the Willis study's
    words or numbers; its landing page names its study, wallette and
    variant and links only the categories it has."""
    import zipfile
    out = tmp_path / "report.zip"
    r = subprocess.run(SNAKEMAKE + ["--report", str(out), "--configfile", "config/config.yaml",
                                    "config/studies/waal_workflow.yaml"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    with zipfile.ZipFile(out) as z:
        html = z.read(next(n for n in z.namelist() if n.endswith("report.html"))).decode()
        files = "".join(z.read(n).decode() for n in z.namelist()
                        if n.endswith((".html", ".csv", ".rst", ".json")) and not n.endswith("report.html"))
    # what the report says: its landing page, its results' captions, its categories (the rest of the page
    # is the report's own code, and the rules' code), and the tables and pages it holds
    said = "".join(re.findall(r'<script id="(?:workflow-desc|results|categories)">(.*?)</script>', html, re.S))
    said += files
    assert len(said) > 10_000 and "Unknown target name" not in said and "System Message" not in said
    low = said.lower()
    found = [w for w in WILLIS_WORDS if w.lower() in low]
    assert not found, found
    landing = open("results/studies/waal/report/workflow.rst").read()
    assert landing.startswith("masonrydem: the waal study, a wallette in horizontal bending") and \
        "per_wall: one draw" in landing
    assert "8 courses of 4 units of 210 x 50 x 100 mm" in landing
    links = set(re.findall(r"^- `?([A-Za-z0-9 -]+)`?_:", landing, re.M))
    assert links == {"Study", "Prediction", "3-D pictures"}, links
