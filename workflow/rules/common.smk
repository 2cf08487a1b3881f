import functools
import shlex
import sys
import os
from pathlib import Path

import yaml
from snakemake.utils import update_config, validate

from masonrydem.errors import InputError
from masonrydem.sources import source_hash
from masonrydem.pipeline import plan
from masonrydem.pipeline.check import check_config
from masonrydem.pipeline.plan import reference_checks, reference_runs

# A nested --config value as YAML types it: Snakemake reads one with YAML's
# base loader, every scalar in it a string (batch="{runs: 10}" gives runs
# "10"); a scalar of the command line's mappings and lists is read again.
def _typed(value):
    if isinstance(value, dict):
        return {k: _typed(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_typed(v) for v in value]
    scalar = yaml.safe_load(value) if isinstance(value, str) and value else value
    return scalar if isinstance(scalar, (int, float, bool, type(None))) else value


for key, value in workflow.config_settings.config.items():
    if isinstance(value, (dict, list)):
        update_config(config, {key: _typed(value)})


# a stage set to null (by a study's own workflow config, over config.yaml's)
# is no stage of this workflow
for key in ("validation", "hard_cases", "half_rate", "reduced", "specimens", "modelform", "accuracy",
            "further_studies", "geometry_formats", "design", "sobol_check", "directions"):
    if key in config and config[key] is None:
        del config[key]
validate(config, "../../config/schema.yaml", set_default=True)
# refused at planning, naming the setting as masonrydem check does (the
# study file's mistakes, NaN or infinite values, overrides the scene refuses)
try:
    check_config(config)
except InputError as e:
    print(f"masonrydem: invalid input: {e}", file=sys.stderr)
    sys.exit(2)
R = config["results"]  # root of every output (config/smoke.yaml: .test/results)
# every rule's software for --sdm conda: the package from this checkout
# (workflow/envs/masonrydem.yaml; the make commands use the venv instead)
ENV = "../envs/masonrydem.yaml"


def get_caption(name):
    """The caption of a report item, written by its rule with the numbers it
    found (template: workflow/report/NAME.rst; written to R/report/NAME.rst)."""
    return os.path.abspath(f"{R}/report/{name}.rst")


def get_caption_file(name):
    """The same caption as an output of its rule (a path relative to the
    working directory, as Snakemake records it: workflow/rules/provenance.smk)."""
    return f"{R}/report/{name}.rst"


def get_template(name):
    return f"workflow/report/{name}.rst"


@functools.cache
def get_solver_hash():
    """Hash of the solver's source: a param of every simulation rule, so that
    a change to src/ reruns the simulations (Snakemake does not track it).
    Read once a workflow: a rule of each batch takes it (a study in runs of
    one has thousands), and the sources do not change while Snakemake
    plans."""
    return source_hash()


def get_python(wildcards, input):
    """This workflow's interpreter (its environment has the package): a
    param that takes the inputs, so Snakemake counts it as derived from
    them and leaves it out of its records.  A run made by another
    interpreter, with the same package and settings, is the same run."""
    return sys.executable


# One simulation through the command line (masonrydem.cli: the one entry
# point of a run); --exit-zero: the job succeeds whenever the run's row is
# written (its status says how the run ended: nothing lost).
RUN = ("{params.python:q} -m masonrydem.cli run {input.scene:q} {params.sets} --out {params.out:q} "
       "--threads {threads} --exit-zero > {log:q} 2>&1")


# A batch of a study's simulations through the same command line: its
# samples (--sample, once each) of one variant and level, advanced in
# lock-step in one process (--lanes at a time), each run's row and curve
# into its own folder (--out with {sample}); --exit-zero as RUN.
RUN_BATCH = ("{params.python:q} -m masonrydem.cli run {input.scene:q} {params.sets} --samples {input.samples:q} "
             "--variant {params.variant} {params.samples} --lanes {params.lanes} --out {params.out:q} "
             "--format json --threads {threads} --exit-zero > {log:q} 2>&1")


def get_batch_samples(samples):
    """The --sample options of a batch."""
    return " ".join(f"--sample {s}" for s in samples)


def get_batch_out(folder):
    """The --out of a batch: each run's folder, {sample} its number (a
    function: Snakemake formats a param's string with the wildcards)."""
    return lambda wildcards: f"{folder}/s{{sample}}"


def get_batch_runtime(samples):
    """A batch job's runtime (minutes; a cluster's limit): a minute a run,
    twice on its retry, at least 10."""
    return lambda wildcards, attempt: attempt * max(10, len(samples))


def get_job_sets(overrides):
    """Scene overrides as the --set options of the command line."""
    return " ".join(f"--set {shlex.quote(o)}" for o in overrides)


def get_run_dir(wildcards, output):
    """The folder of a run's outputs."""
    return os.path.dirname(output[0])


# --- validation ---------------------------------------------------------------
def get_validation_sets(wildcards):
    return get_job_sets(plan.validation_overrides(config, wildcards.case, wildcards.sv)
                        + [f"name=validation:{wildcards.case}_sv{wildcards.sv}", "outputs.state=true"])


def get_validation_outputs():
    if not config.get("validation"):
        return []
    return [f"{R}/validation/summary.csv", f"{R}/validation/load_displacement.png",
            f"{R}/validation/model_numbering.png",
            *(f"{R}/validation/damage_{run}.png" for run in config["validation"]["pictures"]), *get_pages("validation")]


# --- the model-form study ------------------------------------------------------
def get_modelform_results():
    return [f"{R}/modelform/runs/{case}/sv{sv}/{option}/result.parquet"
            for case, sv, option in plan.modelform_runs(config)]


def get_modelform_sets(wildcards):
    return get_job_sets(plan.modelform_overrides(config, wildcards.case, wildcards.sv, wildcards.option)
                        + [f"name=modelform:{wildcards.case}_sv{wildcards.sv}_{wildcards.option}"])


# --- hard cases, reduced models, specimens -------------------------------------
def get_hard_case_sets(wildcards):
    return get_job_sets(plan.hard_case_overrides(config, wildcards.hard) + [f"name=hard_case:{wildcards.hard}"])


def get_stability_outputs():
    return [f"{R}/stability/hard_cases.csv", *get_pages("hard_cases")] if config.get("hard_cases") else []


def get_reduced_results():
    return [f"{R}/reduced/runs/{case}_{model}/result.parquet" for case, model in plan.reduced_runs(config)]


def get_reduced_sets(wildcards):
    return get_job_sets(plan.reduced_overrides(config, wildcards.case, wildcards.model)
                        + [f"name=reduced:{wildcards.case}_{wildcards.model}"])


def get_reduced_outputs():
    return [f"{R}/reduced/summary.csv", *get_pages("reduced")] if config.get("reduced") else []


def get_specimen_scene(wildcards):
    return ancient(plan.specimen_cases(config)[wildcards.case]["scene"])


def get_specimen_sets(wildcards):
    return get_job_sets(plan.specimen_cases(config)[wildcards.case]["overrides"] + [f"name=specimen:{wildcards.case}"])


def get_specimen_outputs():
    return [f"{R}/specimens/summary.csv", *get_pages("specimens")] if config.get("specimens") else []


# --- the stochastic study -------------------------------------------------------
def get_study_runs(kind):
    """Every simulation's result (kind 'result') or curve file."""
    return expand(f"{R}/study/runs/{{variant}}/{{level}}/s{{sample}}/{kind}.json", variant=plan.study_variants(config),
                  level=plan.study_level_dirs(config), sample=range(plan.study(config).samples))


def get_study_scene():
    """The study's scene (its study file's; config's scene serves the
    validation, the hard cases and the other deterministic runs)."""
    return plan.study(config).scene


def get_study_draw():
    """What decides the study's samples, as its draw key (Study.draw_key:
    the samples, seed, variables, correlations, variants, rules and the
    wallette's units and joints), never its levels: a change of the levels
    must not redraw the samples.  The rules that draw read the study
    themselves (plan.study)."""
    return plan.study(config).draw_key()


def get_study_settings():
    """Input -> the scene setting it drives: the study's variables and its
    sweep (for predict: the inputs that change the brick)."""
    s = plan.study(config)
    return {**{v.name: v.setting for v in s.variables}, s.sweep_name: s.sweep_setting}


def get_study_sets(wildcards):
    """A study simulation: the numerics and its level of the swept setting
    (the sample's settings come from the samples file: --samples)."""
    return get_level_sets(wildcards.level)


def get_level_sets(level):
    """get_study_sets of the level folder ``level``."""
    return get_job_sets(plan.effective(config["numerics"], [plan.level_override(config, level)]))


def get_fine_sets(wildcards):
    """A simulation of the accuracy subsample: the fine numerics."""
    return get_job_sets(plan.effective(plan.subsample_fine(config), [plan.pressure(wildcards.sv)]))


# The report's tables, each a page it shows in place (a CSV it only offers
# for download; src/masonrydem/report/tables.py): page name -> (CSV, title,
# report category, caption, the stage that makes the CSV).  Each stage's
# pages are made by a rule of their own (workflow/rules/analysis.smk).
PAGES = {
    "statistics": (f"{R}/study/statistics.csv", "P_max per variant, precompression and failure mode, with 95 % "
                   "intervals", "Study", "statistics", "study"),
    "increase": (f"{R}/study/increase.csv", "Increase of the mean from the lowest to the highest precompression",
                 "Study", "increase", "study"),
    "correlations": (f"{R}/study/correlations.csv", "Pearson correlations of P_max with the random inputs",
                     "Study", "correlations", "study"),
    "sampling_check": (f"{R}/study/sampling_check.csv", "The samples against their targets", "Study",
                       "sampling_check", "study"),
    "sensitivity": (f"{R}/study/sensitivity.csv", "Sobol indices with 95 % intervals, beside the Pearson "
                    "correlations", "Study", "sensitivity", "study"),
    "sobol_check": (f"{R}/sobol_check/check.csv", "The study's Sobol indices against direct estimates from the "
                    "solver", "Study", "sobol_check", "sobol_check"),
    "equations": (f"{R}/study/equations.csv", "Prediction equations (Lasso, 5-fold CV) with 95 % intervals",
                  "Prediction", "equations", "study"),
    "design_comparison": (f"{R}/study/design_comparison.csv", "Design rules against the simulations", "Prediction",
                          "design_comparison", "study"),
    "characteristic": (f"{R}/study/characteristic.csv", "Characteristic (5 %) strengths with 95 % intervals",
                       "Prediction", "characteristic", "study"),
    "paper_comparison": (f"{R}/study/paper_comparison.csv", "The source paper side by side", "Paper side by side",
                         "paper_comparison", "study"),
    "validation": (f"{R}/validation/summary.csv", "Deterministic runs of the scene", "Validation",
                   "validation_summary", "validation"),
    "hard_cases": (f"{R}/stability/hard_cases.csv", "Hard cases: the tails of the inputs", "Stability", "hard_cases",
                   "hard_cases"),
    "reduced": (f"{R}/reduced/summary.csv", "Reduced models against the full model", "Reduced models", "reduced",
                "reduced"),
    "specimens": (f"{R}/specimens/summary.csv", "Direct tension and triplet shear", "Specimens", "specimens",
                  "specimens"),
    "modelform": (f"{R}/modelform/summary.csv", "Every modelling option's change of P_max", "Model form", "modelform",
                  "modelform"),
    "accuracy_runs": (f"{R}/accuracy/runs.csv", "Every accuracy run", "Accuracy", "../report/accuracy_runs.rst",
                      "accuracy"),
    "accuracy_convergence": (f"{R}/accuracy/convergence.csv", "Convergence of P_max along the refinement path",
                             "Accuracy", "accuracy_convergence", "accuracy"),
    "accuracy_choice": (f"{R}/accuracy/choice.csv", "The candidate settings: error and time", "Accuracy",
                        "accuracy_choice", "accuracy"),
    "accuracy_scaling": (f"{R}/accuracy/scaling.csv",
                         "Run time against wallette size, a run per row (the power laws: caption)", "Accuracy",
                         "accuracy_scaling", "accuracy"),
    "accuracy_subsample": (f"{R}/accuracy/subsample.csv", "Study samples at the default and fine settings",
                           "Accuracy", "accuracy_subsample", "accuracy"),
}
# a stage this config does not run has no pages; a study with no source to
# compare has no scorecard
PAGES = {n: p for n, p in PAGES.items() if (p[4] == "study" or config.get(p[4]))
         and (n != "paper_comparison" or config["study"].get("paper"))}


def get_pages(stage):
    """The report's pages of a stage's tables."""
    return [f"{R}/report/tables/{n}.html" for n, p in PAGES.items() if p[4] == stage]


def item(path, caption, category, label, subcategory=None):
    """A result of the report, labelled (the report lists it by its label,
    not its file name); ``caption``: a caption's name (get_caption) or path."""
    return report(path, caption=caption if caption.endswith(".rst") else get_caption(caption), category=category,
                  subcategory=subcategory, labels={"result": label})


def get_further_folder(folder):
    """A further study's results folder: config further_results (the
    committed studies', or a reproduction's own reruns) joined with its
    folder as config gives it (an absolute one stays as it is)."""
    return os.path.join(config["further_results"], folder)


# further studies shown in the report, each run on its own (config
# further_studies), and the geometry study and brick formats of
# geometry_formats, their folders under further_results
FURTHER = {n: dict(s, results=get_further_folder(s["results"])) for n, s in config.get("further_studies", {}).items()}
if config.get("geometry_formats"):
    config["geometry_formats"]["equations"] = get_further_folder(config["geometry_formats"]["equations"])
    for _format in config["geometry_formats"]["formats"].values():
        if _format.get("results"):
            _format["results"] = get_further_folder(_format["results"])


# a further study's figures: file -> (its caption's name, label); its
# curves by mode (a MB each) are in its own report only
FURTHER_FIGURES = {
    "running_mean": ("running_mean", "Running mean of P_max"),
    "brick_share": ("brick_share", "Share of brick failures"),
    "correlation_vs_sigma": ("correlation_vs_sigma", "Correlations against precompression"),
    "scatter_deviation": ("scatter_deviation", "P_max against each random input"),
    "predicted_vs_simulated": ("equations", "Predicted against simulated strength"),
    "design_comparison": ("design_comparison", "Design rules against the simulations"),
    "sensitivity": ("sensitivity", "Sobol indices"),
}


def get_further_figures(study):
    """(path, caption name, label) of a further study's committed figures
    and 3-D pictures (those its own workflow made)."""
    folder = Path(study["results"], "study")
    found = [(f"{folder}/{f}.png", c, label) for f, (c, label) in FURTHER_FIGURES.items()
             if (folder / f"{f}.png").is_file()]
    return found + [(p.as_posix(), "study_pictures", "3-D picture: {} variant, {} failure".format(*p.stem.rsplit("_", 1)))
                    for p in sorted((folder / "pictures").glob("*.png"))]


def get_further_outputs():
    return [f"{R}/report/studies/{n}.html" for n in FURTHER] + \
        ([f"{R}/report/tables/geometry_formats.html"] if config.get("geometry_formats") else [])


def get_design_outputs():
    """The design target's table and page (a workflow config with a
    'design' section: docs/lab-to-design.md)."""
    return [f"{R}/design/design.csv", f"{R}/report/tables/design.html"] if config.get("design") else []


def get_directions_outputs():
    """Both bending directions' table, figure and page (a workflow config
    with a 'directions' section: docs/lab-to-design.md, 11)."""
    return ([f"{R}/study/directions.csv", f"{R}/study/directions.png", f"{R}/report/tables/directions.html"]
            if config.get("directions") else [])


def get_format_runs(name):
    """A format's runs (config geometry_formats): its study's folder's, or
    this workflow's own study's."""
    return f"{config['geometry_formats']['formats'][name].get('results') or R}/study/runs.parquet"


def get_study_outputs():
    names = ("statistics.csv", "correlations.csv", "increase.csv", "sampling_check.csv", "running_mean.png",
             "brick_share.png", "correlation_vs_sigma.png", "scatter_deviation.png", "curves_by_mode.png",
             "equations.csv", "predictor.json", "predicted_vs_simulated.png", "design_comparison.png",
             "characteristic.csv", "sensitivity.png",
             *(["paper_comparison.csv"] if "paper_comparison" in PAGES else []))
    return [*(f"{R}/study/pictures/{v}_{m}.png" for v, m in plan.study_pictures(config)),
            *(f"{R}/study/{name}" for name in names), *get_pages("study"), f"{R}/report/workflow.rst"]


# --- the accuracy study -------------------------------------------------------
def get_accuracy_results(runs):
    return [f"{R}/accuracy/runs/{case}/{setting}/result.parquet" for case, setting in runs]


def get_summary_runs():
    """The accuracy runs the summary reads itself: all but the references'."""
    references = set(reference_runs(config))
    return [run for run in plan.accuracy_runs(config) if run not in references]


def get_accuracy_sets(wildcards):
    return get_job_sets(plan.accuracy_overrides(config, wildcards.case, wildcards.setting)
                        + [f"name=accuracy:{wildcards.case}:{wildcards.setting}"])


def get_scaling_sets(wildcards):
    return get_job_sets(plan.scaling_overrides(config, wildcards.courses)
                        + [f"name=scaling:courses{wildcards.courses}"])


def get_subsample_runs(which):
    """The study's own runs ('default') or their reruns with fine settings."""
    if not config.get("accuracy"):
        return []
    sub = config["accuracy"]["subsample"]
    if which == "default":      # the study's folders of these precompressions (its sweep's)
        st = plan.study(config)
        dirs = dict(zip(plan.study_levels(config), plan.study_level_dirs(config)))
        missing = [sv for sv in sub["precompression_mpa"] if float(sv) not in dirs]
        if not st.sweeps_precompression or missing:
            raise ValueError(f"accuracy.subsample.precompression_mpa: {missing or sub['precompression_mpa']} MPa "
                             f"pairs the study's own runs at these precompressions, but the study file sweeps "
                             f"{st.sweep_setting} at {plan.study_level_dirs(config)}; give the subsample the "
                             f"study's levels, or leave the accuracy target out")
        return expand(f"{R}/study/runs/{{variant}}/{{level}}/s{{sample}}/result.json", variant=st.regression_variant,
                      level=[dirs[float(sv)] for sv in sub["precompression_mpa"]], sample=range(sub["n_samples"]))
    return expand(f"{R}/accuracy/subsample/{{variant}}/sv{{sv}}/s{{sample}}/result.json",
                  variant=plan.study(config).regression_variant, sv=sub["precompression_mpa"],
                  sample=range(sub["n_samples"]))


def get_accuracy_outputs():
    if not config.get("accuracy"):
        return []
    return [f"{R}/accuracy/{name}" for name in (
        "references.csv", "runs.csv", "convergence.csv", "choice.csv", "pareto.png", "scaling.csv", "scaling.png",
        "subsample.csv", "subsample.png")] + get_pages("accuracy")


# --- the Sobol check (workflow/rules/sobol_check.smk) ---------------------------
def get_sobol_check():
    """The check's settings with what follows from the study: its level's
    runs folder, the variant its runs are of (the study's per-wallette
    one), the number of runs; None where the config has no check."""
    c = config.get("sobol_check")
    if not c:
        return None
    st = plan.study(config)         # the level and the variant checked at planning (pipeline/check.py)
    dirs = dict(zip(plan.study_levels(config), plan.study_level_dirs(config)))
    return dict(c, level_dir=dirs[float(c["level"])], variant=st.regression_variant,
                runs=c["base"] * (len(st.variables) + 2))


SOBOL = get_sobol_check()
SOBOL_BATCHES = plan.batches(list(range(SOBOL["runs"])), config) if SOBOL else []


def get_sobol_check_runs(kind):
    return [f"{R}/sobol_check/runs/s{s}/{kind}.json" for s in range(SOBOL["runs"])] if SOBOL else []


def get_sobol_check_outputs():
    return [f"{R}/sobol_check/check.csv", *get_pages("sobol_check")] if SOBOL else []
