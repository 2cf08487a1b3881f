"""A study defined in a file (schema: study_schema.yaml; the Willis study:
config/studies/willis.yaml).

``load_study`` reads and validates it into a typed ``Study``: each random
variable with its distribution in SI (quantities converted in the unit of
the scene setting it drives), the correlations as a mapping of pairs, the
variants and how they draw, the rules and the swept levels as scene
settings.  Every mistake is refused before anything is drawn, the field
named as the study file writes it (prefixed by 'study.') with its value
and, where one fits, a suggestion:

- a key the schema does not know (did you mean the nearest one?), a
  variable's setting that is no numeric setting of a scene (the nearest);
- a dimensional number without its unit (a standard deviation, a bound, a
  level, a rule and a correlation length included; 0 excepted);
- a coefficient of variation outside (0, 1], bounds out of order, a
  lognormal variable whose mean is not above 0;
- a pair correlated twice, a variable correlated with itself, and
  correlations that no joint distribution has (a matrix that is not
  positive definite: the pairs that break it are named);
- fewer samples than the analysis needs (MIN_SAMPLES);
- a variable's lab record (provenance) whose data file is missing or has
  changed since the fit;
- what the scene refuses: the rules, each variable at its mean and each
  swept level (the scene is validated with each), a correlation's
  variables and a regression feature.
"""
import difflib
import hashlib
import math
import re
from dataclasses import replace
from importlib import resources
from pathlib import Path

import numpy as np
from jsonschema import Draft202012Validator

from ..errors import InputError, check_finite
from ..scene import build_scene, is_plain, read_scene, read_yaml, setting_unit, shown, to_si
from .sampling import Variable
from .settings import PER_ITEM
from .terms import MIN_SAMPLES, parse_term
from .typed import Study, mean_of

SCHEMA = read_yaml(resources.files(__package__).joinpath("study_schema.yaml").read_text())


def load_study(path):
    """The typed study of the file at ``path``; InputError names the field."""
    raw = read_scene(path, "study")
    raw = _fail_prefixed(lambda: _validated(raw))
    return _fail_prefixed(lambda: _typed(raw))


def _fail_prefixed(fn):
    try:
        return fn()
    except InputError as e:
        raise InputError(f"study.{e.field}", e.reason) from None


def _validated(raw):
    check_finite(raw)
    errors = sorted(Draft202012Validator(SCHEMA).iter_errors(raw), key=lambda e: list(e.absolute_path))
    if errors:
        e = errors[0]
        field = ".".join(str(p) for p in e.absolute_path) or "study"
        if e.validator == "additionalProperties":
            unknown = sorted(set(e.instance) - set(e.schema.get("properties", {})))
            known = list(e.schema.get("properties", {}))
            raise InputError(f"{field}.{unknown[0]}" if field != "study" else unknown[0],
                             f"is not a key here{_nearest(unknown[0], known)} (the keys: {', '.join(known)})")
        raise InputError(field, e.message)
    return raw


def _nearest(word, words):
    """': did you mean X?' for the nearest of ``words``, or ''."""
    near = difflib.get_close_matches(word, words, n=1, cutoff=0.6)
    return f": did you mean {near[0]!r}?" if near else ""


def numeric_settings():
    """Every numeric setting of a scene, by its dotted path (list items
    without an index)."""
    from ..scene import SCHEMA as SCENE

    def walk(node, path):
        if not isinstance(node, dict):
            return
        if node.get("type") == "number" or (node.get("type") == "array" and isinstance(node.get("items"), dict)
                                            and node["items"].get("type") == "number"):
            yield path
        for key, sub in node.get("properties", {}).items():
            yield from walk(sub, f"{path}.{key}" if path else key)
    return list(walk(SCENE, ""))


def _quantity(value, unit, field, written_unit=None):
    """A study file's quantity in SI: a dimensional setting's value needs
    its unit ('0.35 MPa'; 0 alone is 0 in any unit); ``written_unit``, the
    unit the variable's mean is written in, the suggestion for a number
    without one."""
    if unit and not isinstance(value, str) and value != 0 or unit and isinstance(value, str) and is_plain(value) \
            and float(value) != 0:
        hint = f"{float(value):g} {written_unit}" if written_unit else f"{float(value):g} {shown(unit)[0]}"
        raise InputError(field, f"{value!r} has no unit, and this setting is a quantity ({unit} in SI): write it "
                                f"with its unit: did you mean {hint!r}?")
    return to_si(value, unit, field)


def _written_unit(text):
    """The unit a quantity's text is written in ('0.35 MPa' -> 'MPa'), or None."""
    if not isinstance(text, str) or is_plain(text):
        return None
    m = re.match(r"^\s*[-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?\s*(\S.*?)\s*$", text)
    return m[1] if m else None


def _unit(setting, field):
    unit = setting_unit(setting)
    if unit is None:
        raise InputError(field, f"{setting!r} is not a numeric setting of a scene (scene/schema.yaml)"
                                + _nearest(setting, numeric_settings()))
    return unit


def _variable(name, v):
    field = f"variables.{name}"
    unit = _unit(v["setting"], f"{field}.setting")
    written = _written_unit(v.get("mean"))
    q = {k: _quantity(v[k], unit, f"{field}.{k}", written) for k in ("mean", "sd") if k in v}
    bounds = tuple(_quantity(b, unit, f"{field}.bounds.{i}", written) for i, b in enumerate(v.get("bounds", ())))
    dist = v["distribution"]
    if "cov" in v and not 0 < v["cov"] <= 1:
        raise InputError(f"{field}.cov", f"{v['cov']!r} is not a coefficient of variation: it lies in (0, 1] (sd / "
                                         f"mean; 0.3 is 30 %)")
    if "sd" in q and not q["sd"] > 0:
        raise InputError(f"{field}.sd", f"{v['sd']!r}: a standard deviation is above 0")
    if dist == "lognormal" and "mean" in q and not q["mean"] > 0:
        raise InputError(f"{field}.mean", f"{v['mean']!r}: a lognormal variable's mean is above 0")
    if "cov" in v and "mean" in q and not q["mean"] > 0:
        raise InputError(f"{field}.mean", f"{v['mean']!r}: a cov (sd / mean) needs a mean above 0; give sd instead "
                                          "of cov for a mean of 0 or below")
    if dist in ("uniform", "truncated_normal") and not bounds:
        raise InputError(field, f"a {dist} distribution needs bounds: [min, max]")
    if bounds and not bounds[0] < bounds[1]:
        raise InputError(f"{field}.bounds", f"min must be below max, got {v['bounds']}")
    if dist != "uniform":
        if "mean" not in q or ("cov" in v) == ("sd" in q):
            raise InputError(field, f"a {dist} distribution needs mean and one of cov or sd")
    if v.get("per") and not any(v["setting"].startswith(p[0]) for p in PER_ITEM.values()):
        raise InputError(f"{field}.per", f"{v['setting']} is not a property of units or joints")
    return Variable(name=name, dist=dist, mean=q.get("mean"), cov=v.get("cov"), sd=q.get("sd"),
                    bounds=bounds or None, setting=v["setting"], per=v.get("per"))


def _provenance(name, record):
    """A variable's lab record, its data file there and unchanged since
    the fit (its SHA-256 the record's)."""
    field = f"variables.{name}.provenance.data"
    path = Path(record["data"])
    if not path.is_file():
        raise InputError(field, f"{record['data']}: no such file (a path from the working directory)")
    if hashlib.sha256(path.read_bytes()).hexdigest() != record["sha256"]:
        raise InputError(field, f"{record['data']} has changed since the fit (its SHA-256 is not the record's): "
                                "fit it again (masonrydem fit)")
    return record


def _variant(name, raw, variables):
    """{'draw': ..., 'correlation_length': m or None} of a variant."""
    field, draw = f"variants.{name}", raw["draw"]
    missing = [v.name for v in variables if draw != "wallette" and not v.per]
    if missing:
        raise InputError(f"{field}.draw", f"draws per item, but {', '.join(missing)} has no 'per'")
    if (draw == "field") != ("correlation_length" in raw):
        raise InputError(f"{field}.correlation_length", "a field needs its correlation length, and only a field has one")
    length = _quantity(raw["correlation_length"], "m", f"{field}.correlation_length") if draw == "field" else None
    if length is not None and not length > 0:
        raise InputError(f"{field}.correlation_length", f"must be above 0, got {raw['correlation_length']!r}")
    return {"draw": draw, "correlation_length": length}


def _typed(raw):
    variables = tuple(_variable(n, v) for n, v in raw["variables"].items())
    names = [v.name for v in variables]
    correlations = _correlations(raw.get("correlations", []), names)
    variants = {n: _variant(n, v, variables) for n, v in raw["variants"].items()}
    sweep = raw["sweep"]
    unit = _unit(sweep["setting"], "sweep.setting")
    levels = _levels(sweep["levels"], unit, "sweep.levels")
    check_samples(raw["samples"], "samples")
    sweep_name = sweep.get("name", sweep["setting"].rsplit(".", 1)[-1])
    if sweep_name in names:
        raise InputError("sweep.name", f"{sweep_name!r} is a variable's name too: name the sweep otherwise")
    units = {**{v.name: _unit(v.setting, f"variables.{v.name}.setting") for v in variables}, sweep_name: unit}
    features = tuple((raw.get("regression") or {}).get("features", units))     # each input, linear
    for i, term in enumerate(features):
        _fail_prefixed_at(f"regression.features.{i}", lambda: parse_term(term, units))
    rules = {k: _rule_si(k, v) for k, v in raw.get("rules", {}).items()}
    study = Study(name=raw["name"], scene=raw["scene"], samples=raw["samples"], seed=raw["seed"], variables=variables,
                  correlations=correlations, variants=variants, rules=rules,
                  sweep_setting=sweep["setting"], levels=levels, features=features,
                  sweep_name=sweep_name, units=units, regression_variant=_regression_variant(raw, variants),
                  provenance={n: _provenance(n, v["provenance"]) for n, v in raw["variables"].items()
                              if "provenance" in v})
    _check_against_scene(study)
    return _with_directions(study, raw.get("directions") or {})


def _with_directions(study, given):
    """The study with its bending directions: its scene's own (horizontal
    unless the scene bends vertically) and each further one the file
    names, whose scene bends that way and takes the study as the scene
    does.  Draws per unit or joint cannot be paired between two specimens
    (their units and joints differ): refused with further directions."""
    own = _direction_of(study.scene, "scene", study.rules)
    if own in given:
        raise InputError(f"directions.{own}", f"is the study's own scene's direction (scene: {study.scene} bends "
                                              f"{own}ly): name only the other direction here")
    for name, v in study.variants.items():
        if given and v["draw"] != "wallette":
            raise InputError(f"variants.{name}.draw", f"draws per {v['draw']}, which cannot be paired between the "
                             f"directions' specimens (their units and joints differ): draw per wallette, or give no "
                             "directions")
    for direction, path in given.items():
        field = f"directions.{direction}"
        if (other := _direction_of(path, field, study.rules)) != direction:
            raise InputError(field, f"the scene {path} bends {other}ly, not {direction}ly (its "
                                    "loading.bending.direction)")
        _check_against_scene(replace(study, scene=path), field)
    return replace(study, directions={own: study.scene, **given}, direction=own)


def _direction_of(path, field, rules):
    """The bending direction of a scene file's test (with the study's rules)."""
    scene = _fail_scene(field, lambda: build_scene(path, settings=rules))
    if scene.loading.test != "bending":
        raise InputError(field, f"the scene {path} runs a {scene.loading.test} test: a study's specimens bend")
    return scene.loading.bending.direction


def check_samples(n, field):
    """Refuses fewer samples than the analysis needs (MIN_SAMPLES)."""
    if n < MIN_SAMPLES:
        raise InputError(field, f"{n} samples: the analysis needs at least {MIN_SAMPLES} (each failure mode's "
                                "equation is fitted with nested 5-fold cross-validation over whole samples)")


def _correlations(items, names):
    """The correlations of a study file: (name, name) -> rho, each pair once,
    no variable with itself, and a matrix that is positive definite."""
    out, seen = {}, {}
    for i, c in enumerate(items):
        for k, n in enumerate(c["between"]):
            if n not in names:
                raise InputError(f"correlations.{i}.between.{k}", f"{n!r} is not a variable{_nearest(n, names)} "
                                                                  f"({', '.join(names)})")
        a, b = c["between"]
        if a == b:
            raise InputError(f"correlations.{i}.between", f"{a} with itself: a variable's correlation with itself is "
                                                          "1; name two variables")
        pair = frozenset((a, b))
        if pair in seen:
            raise InputError(f"correlations.{i}", f"{a} and {b} are correlated twice (correlations.{seen[pair]} "
                                                  f"too): give each pair once")
        seen[pair] = i
        out[(a, b)] = float(c["rho"])
    matrix = np.eye(len(names))
    for (a, b), rho in out.items():
        matrix[names.index(a), names.index(b)] = matrix[names.index(b), names.index(a)] = rho
    if out and np.linalg.eigvalsh(matrix)[0] <= 1e-10:
        raise InputError("correlations", "no joint distribution has these correlations (their matrix is not "
                                         f"positive definite): {_breaking(out, names)}")
    return out


def _breaking(correlations, names):
    """The pairs whose correlation makes the matrix not positive definite:
    those without which it is, else those among the variables that weigh
    most in its direction of a non-positive eigenvalue."""

    def smallest(pairs):
        m = np.eye(len(names))
        for (a, b), rho in pairs.items():
            m[names.index(a), names.index(b)] = m[names.index(b), names.index(a)] = rho
        return np.linalg.eigh(m)

    alone = [p for p in correlations if smallest({q: r for q, r in correlations.items() if q != p})[0][0] > 1e-10]
    if not alone:
        vector = np.abs(smallest(correlations)[1][:, 0])
        top = {names[k] for k in np.argsort(-vector)[:3]}
        alone = [p for p in correlations if set(p) <= top]
    return "; ".join(f"{a}-{b} {correlations[(a, b)]:g}" for a, b in alone) + " (lower one of them, or drop it)"


def _regression_variant(raw, variants):
    """The variant the equations are fitted on: the file's regression.variant,
    else the first that draws one value per wallette (a run's inputs are
    then the sample's own); None when no variant does."""
    given = (raw.get("regression") or {}).get("variant")
    if given is None:
        return next((n for n, v in variants.items() if v["draw"] == "wallette"), None)
    if given not in variants:
        raise InputError("regression.variant", f"{given!r} is not a variant ({', '.join(variants)})")
    if variants[given]["draw"] != "wallette":
        raise InputError("regression.variant", f"{given!r} draws per {variants[given]['draw']}: the equations are "
                                               "fitted on a variant that draws one value per wallette")
    return given


def _rule_si(key, value):
    """A rule's value in SI, quantities converted in the unit of the scene
    setting at ``key`` (in a mapping, each of its keys'): a job then passes
    plain numbers, and never loads the units library."""
    if isinstance(value, dict):
        return {k: _rule_si(f"{key}.{k}", v) for k, v in value.items()}
    return _quantity(value, _unit(key, f"rules.{key}"), f"rules.{key}") if setting_unit(key) is not None else value


def _check_against_scene(study, field="scene"):
    """The scene takes the rules, each variable at its mean (or mid-range)
    and each swept level: a setting it does not have, or a value it
    refuses, is found now, named as the study file writes it."""
    base = _fail_scene(field, lambda: read_scene(study.scene))
    _fail_scene("rules", lambda: build_scene(base, settings=study.rules))
    for v in study.variables:
        _fail_scene(f"variables.{v.name}", lambda: build_scene(base, settings={**study.rules, v.setting: mean_of(v)}))
    _check_levels(study, base, study.levels, "sweep.levels", lambda e: f"the scene refuses it: {e}")


def _check_levels(study, base, levels, field, reason):
    for i, level in enumerate(levels):
        try:
            build_scene(base, settings={**study.rules, study.sweep_setting: level})
        except InputError as e:
            raise InputError(f"{field}.{i}", reason(e)) from None


def _levels(texts, unit, field):
    """The swept levels in SI, each given once: a level that is another
    one in other words ('100 kPa' and '0.1 N/mm2') is refused, naming
    both (two runs folders of one level would collide)."""
    levels = []
    for i, x in enumerate(texts):
        si = _quantity(x, unit, f"{field}.{i}")
        for j, before in enumerate(levels):
            if math.isclose(si, before, rel_tol=1e-9, abs_tol=1e-12):
                raise InputError(f"{field}.{i}", f"{x!r} is the level {texts[j]!r} ({field}.{j}) again: give each "
                                                 "level once")
        levels.append(si)
    return tuple(levels)


def with_levels(study, levels, field):
    """The study with other ``levels`` of its swept setting (quantities or
    SI), each converted and checked by the scene as the file's are;
    InputError names ``field``.N."""
    unit = _unit(study.sweep_setting, field)
    si = _levels(levels, unit, field)
    _check_levels(study, read_scene(study.scene), si, field, lambda e: e.reason)
    return replace(study, levels=si)


def _fail_prefixed_at(field, fn):
    try:
        return fn()
    except ValueError as e:
        raise InputError(field, str(e)) from None


def _fail_scene(field, fn):
    try:
        return fn()
    except InputError as e:
        raise InputError(field, f"the scene refuses it: {e}") from None
