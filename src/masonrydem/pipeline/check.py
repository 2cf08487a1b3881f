"""``masonrydem check FILE``: a scene or a study file validated, and what
it would run counted and estimated from its own numbers alone: nothing is
built, drawn or run.  A scene: the model it builds and one run's time and
memory.  A study file: its variables, correlations, variants and levels as
read (in SI and as written), the runs it makes, and their cost from its
scene's estimate.

The time is the cost of one step times the steps.  The cost of a step
is the sum of each kind of item times its measured cost on one core
(docs/speed.md, ``make bench``: a joint sub-contact 15 ns, a linear cell
37 ns, a tetrahedral zone 25 ns elasto-plastic or 17 ns elastic, the
node update about 9 ns a node).  The steps are bounded by the drive: the
ramp and the displacement limit over the rate, at most the test's
max_steps, and the precompression's own stage.  A run that reaches its
load drop, or passes its peak, stops sooner."""
import difflib
import math
import re

from ..analysis.needs import MIN_RUNS, lower_end_runs
from ..errors import InputError
from ..scene import SCHEMA as SCENE_SCHEMA
from ..scene import build_scene, model_size, read_scene, shown, to_shown
from ..study.terms import MIN_SAMPLES
from . import plan

# seconds per step and item, one core (docs/speed.md, 2026-11-25)
COST = dict(sub_contacts=15e-9, cells=37e-9, zones_plastic=25e-9, zones_elastic=17e-9, nodes=9e-9)


def step_seconds(scene, size):
    """The estimated cost of one step (s) of the scene's model of ``size``."""
    plastic = scene.physics.model.plastic
    zones = COST["zones_plastic" if plastic else "zones_elastic"]
    return (size["sub_contacts"] * COST["sub_contacts"] + size["cells"] * COST["cells"]
            + size["tetrahedra"] * zones + size["nodes"] * COST["nodes"])


def step_bound(scene):
    """(steps at most: the test's drive, the precompression stage's at most)."""
    d = scene.loading.drive
    drive = min(d.max_steps, d.ramp_steps + math.ceil(d.max_displacement / d.rate))
    pre = scene.loading.precompression
    return drive, (pre.max_steps if pre.pressure > 0 else 0)


def is_study(path):
    """Whether the YAML file at ``path`` is a study file (it names its
    variables and its sweep) rather than a scene."""
    raw = read_scene(path, "file")
    return "variables" in raw or "sweep" in raw


def summary(scene):
    """The lines ``check`` prints for a validated scene."""
    g, ph, num = scene.geometry, scene.physics, scene.discretization
    size = model_size(g, ph, num, scene.loading)
    per_step = step_seconds(scene, size)
    drive, pre = step_bound(scene)
    L, H, T = g.unit_length, g.unit_height, g.unit_width
    cracks = g.n_units if ph.model.crack_interface else 0
    joints = f"{len(g.joints) + cracks} joints" + (f": {len(g.joints)} mortar joints and {cracks} crack interfaces "
                                                    "of the potential-crack units" if cracks else "")
    test = scene.loading.test
    if test == "bending":
        test = ("vertical bending (plane of failure parallel to the bed joints)"
                if scene.loading.bending.direction == "vertical"
                else "horizontal bending (plane of failure perpendicular to the bed joints)")
    ends = ", straight ends" if g.ends == "straight" else ""
    lines = [
        f"scene {scene.name!r}: valid",
        f"  specimen: {g.courses} courses x {g.units_per_course} units of {L * 1e3:g} x {H * 1e3:g} x "
        f"{T * 1e3:g} mm{ends}, joints {g.joint_thickness * 1e3:g} mm ({g.n_units} units, {joints})",
        f"  physics: {ph.blocks} blocks, {ph.joints} joints; test: {test}",
        f"  model: {size['nodes']:,} nodes, {size['tetrahedra']:,} tetrahedra, {size['cells']:,} cells, "
        f"{size['sub_contacts']:,} sub-contacts (upper estimates; cells {list(num.cells)}, "
        f"refine {num.refine_label})",
        f"  memory: about {size['bytes'] / 1e6:.0f} MB at most",
        f"  time: about {per_step * 1e6:.0f} us a step on one core; the test's drive allows at most "
        f"{drive:,} steps ({_duration(drive * per_step)})"
        + (f", the precompression at most {pre:,} more" if pre else ""),
        "  a run that reaches its load drop, or passes its peak (loading.bending.past_peak), stops sooner",
        "  nothing was built or run",
    ]
    return lines


def study_summary(study):
    """The lines ``check`` prints for a typed study (study.file.load_study:
    everything in it already checked): what it draws, what it runs, and
    the runs' cost from its scene's estimate at the mean properties and
    each level."""
    scene = build_scene(study.scene, settings=study.mean_settings())
    runs = study.samples * len(study.variants) * len(study.levels)
    per_step = step_seconds(scene, model_size(scene.geometry, scene.physics, scene.discretization, scene.loading))
    drive, _ = step_bound(scene)
    lines = [f"study {study.name!r}: valid", f"  scene: {study.scene} ({scene.name})"]
    for v in study.variables:
        unit = study.units[v.name]
        spread = f"cov {v.cov:g}" if v.cov is not None else (f"sd {_shown(v.sd, unit)}" if v.sd is not None else "")
        where = f"{v.bounds and ' cut to ' + ' to '.join(_shown(b, unit) for b in v.bounds) or ''}"
        mean = _shown(v.mean, unit) if v.mean is not None else "uniform"
        lines.append(f"  {v.name}: {v.dist}, mean {mean}, {spread}{where} -> {v.setting}"
                     + (f" (one per {v.per} where a variant draws per item)" if v.per else ""))
        if v.name in study.provenance:
            r = study.provenance[v.name]
            lines.append(f"    fitted to {r['data']} ({r['n']} results, its SHA-256 the record's) x "
                         f"{r['conversion']['factor']:g}")
    lines += [f"  correlation {a}-{b}: {rho:g}" for (a, b), rho in study.correlations.items()]
    lines += [f"  variant {n}: draws {v['draw']}" + (f", correlation length {v['correlation_length']:g} m"
                                                      if v["correlation_length"] else "")
              for n, v in study.variants.items()]
    unit = study.units[study.sweep_name]
    lines += [f"  sweep {study.sweep_name} ({study.sweep_setting}): "
              + ", ".join(_shown(x, unit) for x in study.levels),
              f"  regression: {', '.join(study.features)} on the variant {study.regression_variant or '(none)'}",
              f"  runs: {study.samples} samples x {_count(len(study.variants), 'variant')} x "
              f"{len(study.levels)} levels = "
              f"{runs:,}; each drive at most {drive:,} steps, {_duration(drive * per_step)} on one core (the scene's "
              "estimate at the mean properties), before a precompression's own steps; a run that passes its peak "
              "stops sooner",
              *study_outputs(study),
              "  nothing was drawn or run"]
    return lines


def study_outputs(study):
    """What the study's sample count lets its analysis give, from the
    analysis's own minimums: the prediction equations (a failure mode
    needs MIN_SAMPLES samples failing in it, in the regression variant),
    the Sobol indices (MIN_RUNS runs in a group: a variant, level and
    failure mode, or all modes) and the non-parametric 5 % fractile's
    interval (a lower end needs the n at which order_ranks gives one)."""
    n, levels = study.samples, len(study.levels)
    lower = lower_end_runs()
    equations = (f"    prediction equations (variant {study.regression_variant}): a failure mode gets one where at "
                 f"least {MIN_SAMPLES} of the {n} samples fail in it at some level; else the other mode's stands for "
                 "both, and `predict` says so" if study.regression_variant else
                 "    prediction equations: none (no variant draws per wallette)")
    sobol = (f"    Sobol indices: {n} runs per variant and level, all modes together; a failure mode's own need "
             f"{MIN_RUNS} runs failing in it at a level" if n >= MIN_RUNS else
             f"    Sobol indices: none ({n} runs per variant and level; a group needs {MIN_RUNS}: give samples: "
             f"{MIN_RUNS} or more)")
    fractile = (f"    5 % fractiles: lognormal with its 95 % interval; the non-parametric one's interval "
                + ("has both ends" if lower <= n else f"has no lower end ({n} runs per variant and level; it needs "
                                                      f"{lower})"))
    return [f"  outputs at {n} samples x {levels} levels:", equations, sobol, fractile]


def _count(n, word):
    return f"{n} {word}" + ("" if n == 1 else "s")


def _shown(x, unit):
    text, _, _ = shown(unit)
    return f"{to_shown(x, unit):g} {text}".rstrip()


_UNEXPECTED = re.compile(r"Additional properties are not allowed \('([^']+)' was unexpected\)")
_REQUIRED = re.compile(r"'([^']+)' is a required property")
_IN_STUDY = re.compile(r".*the scene refuses it: (?P<field>[\w.]+): (?P<reason>.*)")
_STUDY = "the source paper's model (docs/study.md, section 3)"
# what a scene's material property may be set to where the user has no value
# of their own, and where that value comes from
SUGGESTED = {
    "materials.units.E": ("15 GPa", "the source paper's bricks (docs/study.md, section 3); take your units' own"),
    "materials.units.nu": ("0.2", _STUDY),
    "materials.units.ft": ("3.75 MPa", "the source paper's bricks (docs/study.md, section 3); take your units' own"),
    "materials.units.c_ratio": ("1.5", f"c_u = 1.5 f_tu, {_STUDY}"),
    "materials.units.phi": ("35 deg", "not given by the source paper: the committed scenes' choice "
                                      "(docs/study.md, section 3)"),
    "materials.units.density": ("1900 kg/m^3", "the Willis scene's, a fired-clay brick's; quasi-static runs scale "
                                               "the masses (docs/formulation.md)"),
    "materials.joints.ft": ("0.30 MPa", "the source paper's mean bond (docs/study.md, section 3); take your "
                                        "bond-wrench tests' (docs/lab-to-design.md)"),
    "materials.joints.c_ratio": ("1.2", f"c_j = 1.2 f_tj, {_STUDY}"),
    "materials.joints.phi": ("35 deg", f"initial and residual, {_STUDY}"),
    "materials.joints.GII_ratio": ("10.0", f"G_II = 10 G_I, {_STUDY}"),
    "materials.joints.Em_ratio": ("0.1", f"E_m = 0.1 E_b, {_STUDY}"),
    "materials.joints.ks_ratio": ("0.4", f"k_s = 0.4 k_n, {_STUDY}"),
}


def explained(error):
    """An InputError of a scene, with a suggestion where one fits: a key the
    scene's schema does not know is named with the nearest one it does; a
    missing material property with a value and where it comes from
    (SUGGESTED)."""
    field, reason = error.field, error.reason
    nested = _IN_STUDY.fullmatch(reason)            # a study's scene: 'the scene refuses it: FIELD: REASON'
    if nested:
        field, reason = nested["field"], nested["reason"]
    required = _REQUIRED.fullmatch(reason)
    if required and f"{field}.{required[1]}" in SUGGESTED:
        value, source = SUGGESTED[f"{field}.{required[1]}"]
        return InputError(f"{field}.{required[1]}", ("in the study's scene: " if nested else "")
                          + f"missing: a scene gives every material property; where you have no value of your "
                            f"own, {value} is {source}")
    m = _UNEXPECTED.fullmatch(error.reason)
    if not m:
        return error
    node = SCENE_SCHEMA
    for key in ([] if error.field == "scene" else error.field.split(".")):
        node = node.get("properties", {}).get(key, {}) if isinstance(node, dict) else {}
    known = list(node.get("properties", {})) if isinstance(node, dict) else []
    near = difflib.get_close_matches(m[1], known, n=1, cutoff=0.6)
    field = m[1] if error.field == "scene" else f"{error.field}.{m[1]}"
    return InputError(field, "is not a setting here" + (f": did you mean {near[0]!r}?" if near else "")
                      + (f" (the settings: {', '.join(known)})" if known else ""))


def _duration(seconds):
    if seconds < 120:
        return f"{seconds:.1f} s"
    if seconds < 7200:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


# --- a workflow's config, checked at planning -----------------------------------
def planned_scenes(config):
    """(where, scene file, overrides) of every kind of simulation the config
    plans: ``where`` names the config's setting (and the run) it comes from."""
    scene, numerics = config["scene"], config["numerics"]
    out = [("numerics", scene, numerics)]
    out += [(f"study levels ({level})", plan.study(config).scene,
             plan.effective(numerics, [plan.level_override(config, level)]))
            for level in plan.study_level_dirs(config)]
    v = config.get("validation") or {"cases": [], "precompression_mpa": []}
    out += [(f"validation.cases ({c['name']} at {sv} MPa)", scene, plan.validation_overrides(config, c["name"], sv))
            for c in v["cases"] for sv in v["precompression_mpa"]]
    out += [(f"hard_cases ({run})", scene, plan.hard_case_overrides(config, run))
            for run in plan.hard_case_jobs(config)]
    out += [(f"reduced ({case}, model {model})", scene, plan.reduced_overrides(config, case, model))
            for case, model in plan.reduced_runs(config)]
    out += [(f"specimens ({name})", c["scene"], c["overrides"]) for name, c in plan.specimen_cases(config).items()]
    out += [(f"modelform ({case} at {sv} MPa, {option})", scene, plan.modelform_overrides(config, case, sv, option))
            for case, sv, option in plan.modelform_runs(config)]
    out += [(f"accuracy ({case}, setting {setting})", scene, plan.accuracy_overrides(config, case, setting))
            for case, setting in plan.accuracy_runs(config)]
    out += [(f"accuracy.scaling_courses ({n})", scene, plan.scaling_overrides(config, n))
            for n in plan.scaling_courses(config)]
    if config.get("accuracy"):
        out += [(f"accuracy.subsample.fine ({sv} MPa)", scene,
                 plan.effective(plan.subsample_fine(config), [plan.pressure(sv)]))
                for sv in config["accuracy"]["subsample"]["precompression_mpa"]]
    return out


def check_config(config):
    """Refuses, at planning, what config/schema.yaml cannot: a NaN or an
    infinity anywhere, and overrides that a planned simulation's scene
    refuses (each distinct
    scene and overrides validated as the run will be; cheap: no model is
    built).  Raises InputError naming the config's setting."""
    from ..errors import check_finite
    check_finite(config)
    scenes, done = {}, set()
    for where, scene, overrides in planned_scenes(config):
        if (scene, tuple(overrides)) in done:
            continue
        done.add((scene, tuple(overrides)))
        try:
            if scene not in scenes:
                scenes[scene] = read_scene(scene)
            build_scene(scenes[scene], overrides)
        except InputError as e:
            raise InputError(where, f"the scene {scene} with the overrides {list(overrides)} is refused: {e}") from None
    check_sobol(config)
    return config


def check_sobol(config):
    """The Sobol check (config sobol_check) at a level of the study, on a
    variant that draws per wallette."""
    check = config.get("sobol_check")
    if not check:
        return
    from . import plan
    levels = plan.study_levels(config)
    if float(check["level"]) not in levels:
        raise InputError("sobol_check.level", f"{check['level']} is not a level of the study "
                                              f"({', '.join(f'{x:g}' for x in levels)}): give one of them, or "
                                              "set sobol_check: null")
    if plan.study(config).regression_variant is None:
        raise InputError("sobol_check", "the study has no variant that draws per wallette, whose indices the "
                                        "check is for: set sobol_check: null")
