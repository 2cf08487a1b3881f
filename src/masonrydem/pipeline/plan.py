"""What the workflow runs: the run ids of every stage and the scene
overrides of each simulation job, from the workflow's config
(config/config.yaml, validated by config/schema.yaml).  The file paths are
the workflow's (workflow/rules/common.smk); this module names the runs and
says what each one overrides."""
from dataclasses import replace
from functools import lru_cache

import yaml

from ..errors import InputError
from ..scene import PRECOMPRESSION, build_scene, to_shown
from ..study.file import check_samples, load_study, with_levels


def effective(*lists):
    """Scene overrides in order, without those a later one replaces (same
    key): the parameters then say only what a run uses, so that changing a
    default that a run overrides anyway does not rerun it."""
    flat = [o for lst in lists for o in lst]
    keys = [o.split("=", 1)[0] for o in flat]
    return [o for i, o in enumerate(flat) if keys[i] not in keys[i + 1:]]


def _by_name(cases):
    return {c["name"]: c["overrides"] for c in cases}


# --- validation ----------------------------------------------------------
def validation_runs(config):
    """Run ids '<case>_sv<sigma_v>': every case at every precompression."""
    v = config.get("validation")
    return [f"{c['name']}_sv{sv}" for c in v["cases"] for sv in v["precompression_mpa"]] if v else []


def validation_overrides(config, case, sv):
    """One validation run: its case's overrides plus the precompression
    (``sv`` in MPa, as in its run id)."""
    return effective(config["numerics"], _by_name(config["validation"]["cases"])[case], [pressure(sv)])


# --- hard cases ---------------------------------------------------------------
def hard_case_jobs(config):
    """Run id -> scene overrides (after config 'numerics') of the hard cases
    (config 'hard_cases') and of their half-rate reruns
    ('<name>_half_rate', overrides config 'half_rate')."""
    jobs = {}
    for c in config.get("hard_cases", []):
        jobs[c["name"]] = list(c["overrides"])
        if c.get("half_rate"):
            jobs[c["name"] + "_half_rate"] = list(c["overrides"]) + list(config["half_rate"])
    return jobs


def hard_case_expect(config):
    """Case -> the failure mode its strengths call for ('any': a
    trustworthy number or a clear status)."""
    return {c["name"]: c["expect"] for c in config.get("hard_cases", [])}


def hard_case_overrides(config, run):
    return effective(config["numerics"], hard_case_jobs(config)[run])


# --- reduced models ---------------------------------------------------------
def reduced_runs(config):
    """(case, model) of every reduced-model run, case by case."""
    r = config.get("reduced")
    return [(c["name"], m) for c in r["cases"] for m in r["models"]] if r else []


def reduced_overrides(config, case, model):
    r = config["reduced"]
    return effective(config["numerics"], _by_name(r["cases"])[case], r["models"][model])


# --- the model-form study -------------------------------------------------------
def modelform_options(assumptions):
    """The options of config 'modelform''s ``assumptions`` by run name:
    '<assumption>_<k>' (k = 1, 2, ...) -> (assumption, option), and
    'baseline' (the scene as it stands) -> ('baseline', None)."""
    return {"baseline": ("baseline", None)} | {f"{a['name']}_{k}": (a["name"], o) for a in assumptions
                                               for k, o in enumerate(a["options"], start=1)}


def modelform_labels(config):
    """Run name -> (assumption, the option's label; 'as modelled' for the
    baseline) of the model-form study."""
    return {k: (name, o["label"] if o else "as modelled")
            for k, (name, o) in modelform_options(config["modelform"]["assumptions"]).items()}


def modelform_runs(config):
    """(case, sigma_v in MPa, option name) of every model-form run: per
    case and level the baseline and each option of each assumption."""
    m = config.get("modelform")
    if not m:
        return []
    return [(c["name"], sv, o) for c in m["cases"] for sv in m["precompression_mpa"]
            for o in modelform_options(m["assumptions"])]


def modelform_overrides(config, case, sv, option):
    m = config["modelform"]
    _, opt = modelform_options(m["assumptions"])[option]
    return effective(config["numerics"], _by_name(m["cases"])[case], [pressure(sv)], opt["overrides"] if opt else [])


# --- further specimens ------------------------------------------------------
def specimen_cases(config):
    """Case -> {name, scene, overrides} of the further specimens."""
    return {c["name"]: c for c in config.get("specimens", [])}


# --- the stochastic study -----------------------------------------------------
def study(config):
    """The typed study of the config: its study file (study.file), with
    the config's samples, seed and levels where given (config/smoke.yaml:
    a small study of the same file)."""
    s = config["study"]
    levels = tuple(str(x) for x in s["levels"]) if "levels" in s else None
    return _study(s["file"], s.get("samples"), s.get("seed"), levels, s.get("direction"))


@lru_cache(maxsize=None)
def _study(path, samples, seed, levels, direction=None):
    st = load_study(path)
    if direction is not None:
        try:
            st = st.in_direction(direction)
        except InputError as e:
            raise InputError("study.direction", e.reason) from None
    if samples is not None:
        check_samples(samples, "study.samples")
    changes = {k: v for k, v in (("samples", samples), ("seed", seed)) if v is not None}
    if levels is not None:
        st = with_levels(st, [_number(x) for x in levels], "study.levels")
    return replace(st, **changes)


def _number(text):
    try:
        return float(text)
    except ValueError:
        return text


def study_levels(config):
    """The study's levels of its swept setting, in the unit the runs table
    shows them in (the precompression in MPa)."""
    st = study(config)
    return [to_shown(level, st.units[st.sweep_name]) for level in st.levels]


def study_level_dirs(config):
    """The runs' folder of each level (the wildcard level): the sweep's
    name and the level as shown, sigma_v0.15."""
    return [f"{study(config).sweep_name}{x!r}" for x in study_levels(config)]


def batches(samples, config):
    """``samples`` (numbers) in the batches of config batch.runs each: a
    simulation job each."""
    size = config["batch"]["runs"]
    return [samples[i:i + size] for i in range(0, len(samples), size)]


def study_batches(config):
    """The study's simulations as jobs: [(variant, level folder, samples)]."""
    samples = list(range(study(config).samples))
    return [(v, d, b) for v in study_variants(config) for d in study_level_dirs(config) for b in batches(samples, config)]


def subsample_batches(config):
    """The accuracy subsample's simulations at fine settings as jobs:
    [(variant, precompression in MPa, samples)] (none without the accuracy
    stage)."""
    if not config.get("accuracy"):
        return []
    sub = config["accuracy"]["subsample"]
    samples = list(range(sub["n_samples"]))
    return [(study(config).regression_variant, sv, b) for sv in sub["precompression_mpa"]
            for b in batches(samples, config)]


def level_override(config, level):
    """The scene override of a level: by its folder name (the wildcard) or
    its value as shown (a runs table's level column)."""
    st = study(config)
    dirs, shown = study_level_dirs(config), study_levels(config)
    k = dirs.index(level) if isinstance(level, str) else min(range(len(shown)), key=lambda i: abs(shown[i] - level))
    return f"{st.sweep_setting}={float(st.levels[k])}"


def analysis(config):
    """What the study's analysis needs of its study file (``spec``)."""
    return spec(study(config))


def spec(st):
    """What a study's analysis needs of its typed study: its name, the
    equations' terms, each input's column in the runs table, the swept
    setting, its name, column and unit shown, the variables' means (in the
    columns' units), each input's SI unit, the variants and the one the
    equations are fitted on (None: no equations), and whether it sweeps the
    precompression.  Plain data: a workflow rule's parameter."""
    return dict(study=st.name, terms=list(st.features), columns=st.columns(), setting=st.sweep_setting,
                level=st.sweep_name, level_column=st.level_column(), level_unit=st.level_unit(), means=st.means(),
                units=dict(st.units), variants=list(st.variants), regression_variant=st.regression_variant,
                precompression=st.sweeps_precompression)


def further_study(workflow_config):
    """What a further study's report page needs of its study file (its
    workflow config's study.file): the variant its equations are fitted
    on, its swept setting's column and the unit it is shown in."""
    with open(workflow_config) as f:
        path = yaml.safe_load(f)["study"]["file"]
    st = _study(path, None, None, None)
    return dict(variant=st.regression_variant, level_column=st.level_column(), level_unit=st.level_unit())


# the report's categories, what each holds, and the config section that makes it
CATEGORIES = [
    ("Study", "the statistics, correlations, the increase over the swept levels, the curves by failure mode, the "
              "running means, the Sobol indices", None),
    ("Prediction", "the Lasso-selected prediction equations, the design comparison and the characteristic "
                   "strengths", None),
    ("Paper side by side", "every figure the source paper publishes beside ours, with our 95 % intervals", "paper"),
    ("Model form", "what each modelling assumption does to P_max", "modelform"),
    ("Accuracy", "how the numerical settings were chosen, and what finer ones would change", "accuracy"),
    ("Validation", "deterministic runs of the scene", "validation"),
    ("Stability", "hard cases: the tails of the inputs, high precompression, tiny fracture energies", "hard_cases"),
    ("Reduced models", "rigid and elastic units against the full model", "reduced"),
    ("Specimens", "the further tests: direct tension and triplet shear", "specimens"),
    ("Further studies", "other studies, each run on its own", "further_studies"),
    ("3-D pictures", "the final states, damage in colour", None),
]
DRAWS = {"wallette": "one draw of the properties for the whole wallette",
         "items": "one draw per unit and per joint",
         "field": "a random field over the units and joints"}


def report_spec(config):
    """What the report's landing page says of this workflow: the study's
    name, its wallette and test (from its scene with its rules), what each
    variant draws, and the report's categories with what each holds
    (those of the stages this config runs)."""
    st = study(config)
    sc = build_scene(st.scene, settings=st.rules)
    g = sc.geometry
    brick = " x ".join(f"{1e3 * x:g}" for x in (g.unit_length, g.unit_height, g.unit_width))
    test = {"bending": "four-point out-of-plane horizontal bending", "tension": "direct tension",
            "triplet": "triplet shear"}[sc.loading.test]
    variants = {n: DRAWS[v["draw"]] + (f" (correlation length {1e3 * v['correlation_length']:g} mm)"
                                       if v["correlation_length"] else "") for n, v in st.variants.items()}
    present = {"paper": bool(config["study"].get("paper"))} | {k: bool(config.get(k)) for _, _, k in CATEGORIES if k
                                                              and k != "paper"}
    present["further_studies"] = present["further_studies"] or bool(config.get("geometry_formats"))
    return dict(study=st.name, scene=sc.name, test=test, precompression=st.sweeps_precompression,
                wallette=f"{g.courses} courses of {g.units_per_course} units of {brick} mm in running bond with "
                         f"{1e3 * g.joint_thickness:g} mm joints",
                variants=variants, draws={n: v["draw"] for n, v in st.variants.items()},
                inputs=[v.name for v in st.variables],
                categories=[[name, what] for name, what, key in CATEGORIES if key is None or present[key]])


def study_variants(config):
    return list(study(config).variants)


def study_pictures(config):
    """(variant, failure mode) of the study's 3-D pictures."""
    return [(v, m) for v in study_variants(config) for m in ("joint", "brick")]


# --- the accuracy study --------------------------------------------------------
def path_setting(cells):
    """Setting id of a level of the refinement path."""
    return "path_c{}x{}x{}".format(*cells)


def path_settings(config):
    """Setting ids of the refinement path (the elasto-plastic model, each
    case's converged reference), coarse to fine."""
    acc = config.get("accuracy")
    return [path_setting(c) for c in acc["path"]["cells"]] if acc else []


def candidate_settings(config):
    """Setting ids of the candidates for the defaults."""
    acc = config.get("accuracy")
    return [c["name"] for c in acc["candidates"]] if acc else []


def accuracy_settings(acc, case):
    """Setting id -> overrides (after config 'numerics' and the case's) of
    every run of ``case``: the path levels (the path's overrides and their
    cells), the candidates, the defaults themselves ('default') and one
    setting changed at a time around the defaults or around the candidate
    or path level named by 'around'.  A case's 'path_overrides' apply to its
    path levels only."""
    own = next(c.get("path_overrides", []) for c in acc["cases"] if c["name"] == case)
    path = {path_setting(c): [*acc["path"]["overrides"], *own, f"numerics.cells={list(c)}"]
            for c in acc["path"]["cells"]}
    named = {**path, **{c["name"]: list(c["overrides"]) for c in acc["candidates"]}}
    out = {**named, "default": []}
    for s in acc["settings"]:
        if "around" in s and s["around"] not in named:
            raise ValueError(f"config accuracy.settings {s['name']}.around: {s['around']!r} is neither a candidate "
                             "nor a path level")
        if case in s.get("cases", [c["name"] for c in acc["cases"]]):
            for v in s["values"]:
                out[f"{s['name']}_{v}"] = [*named.get(s.get("around"), []), f"{s['key']}={v}"]
    return out


def accuracy_baselines(config):
    """One-at-a-time setting id -> the setting it varies ('default' or its 'around')."""
    acc = config.get("accuracy")
    return {f"{s['name']}_{v}": s.get("around", "default") for s in acc["settings"] for v in s["values"]} if acc else {}


def accuracy_cases(config):
    acc = config.get("accuracy")
    return [c["name"] for c in acc["cases"]] if acc else []


def accuracy_runs(config):
    """(case, setting) of every accuracy run."""
    acc = config.get("accuracy")
    return [(c["name"], s) for c in acc["cases"] for s in accuracy_settings(acc, c["name"])] if acc else []


def accuracy_overrides(config, case, setting):
    acc = config["accuracy"]
    return effective(config["numerics"], _by_name(acc["cases"])[case], accuracy_settings(acc, case)[setting])


def scaling_courses(config):
    acc = config.get("accuracy")
    return acc["scaling_courses"] if acc else []


def scaling_settings(config):
    """The path levels, whose run time gives the cost against the cells per edge."""
    return path_settings(config)


def scaling_overrides(config, courses):
    """The defaults on a wallette of ``courses`` courses (run time against
    the number of units)."""
    return config["numerics"] + [f"geometry.courses={courses}"]


def subsample_fine(config):
    """The fine settings of the accuracy subsample (complete: independent
    of the defaults)."""
    acc = config.get("accuracy")
    return acc["subsample"]["fine"] if acc else []


def reference_runs(config):
    """(case, setting) of the runs that make the accuracy study's
    references: the path levels and the settings varied around one.  Their
    results are kept in a table of their own (rule accuracy_references,
    hours of runs), which the summary reads instead of rerunning them
    whenever the defaults move; the path's overrides pin the numerics the
    defaults set (damping)."""
    acc = config.get("accuracy")
    if not acc:
        return []
    path = set(path_settings(config))
    around = {f"{s['name']}_{v}" for s in acc["settings"] if s.get("around") in path for v in s["values"]}
    return [(c, s) for c, s in accuracy_runs(config) if s in path or s in around]


def reference_checks(config):
    """(case, setting) of the coarsest path level of every case: rerun with
    each summary and compared with the references' table, so a table made
    by another solver is refused, not read."""
    first = path_settings(config)[:1]
    return [(c, s) for c, s in accuracy_runs(config) if s in first]


def pressure(sv_mpa):
    """The override of a precompression level (MPa)."""
    return f"{PRECOMPRESSION}={float(sv_mpa) * 1e6}"
