"""Scenes: a specimen described in YAML, validated before anything runs
(specimen.py builds it into a Model).

A scene (schema: scene_schema.yaml, defaults = the Willis wallette of
study.md) declares geometry, physics, materials, loading, numerics and
outputs.  ``load_scene`` reads it, applies ``--set`` overrides and checks it;
every error names the field (a dotted path) and the reason.
"""
import copy
import re
from dataclasses import dataclass
from importlib import resources

import numpy as np
import yaml
from jsonschema import Draft202012Validator, validators

from .errors import InputError
from .laws import BLOCK_MODELS, JOINT_LAWS, MohrCoulomb
from .masonry import crack_band_error, running_bond_joints, wall_length


class _Loader(yaml.SafeLoader):
    """YAML loader that also reads 15e9 or 0.3e6 as floats (YAML 1.1, and so
    PyYAML, wants 15.0e+9)."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"""^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
                   |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
                   |\.[0-9_]+(?:[eE][-+]?[0-9]+)?
                   |[-+]?\.(?:inf|Inf|INF)
                   |\.(?:nan|NaN|NAN))$""", re.X),
    list("-+0123456789."))


def read_yaml(text):
    return yaml.load(text, Loader=_Loader)


SCHEMA = read_yaml(resources.files(__package__).joinpath("scene_schema.yaml").read_text())
# the choices of physics come from the tables of laws (laws.py)
SCHEMA["properties"]["physics"]["properties"]["blocks"]["enum"] = list(BLOCK_MODELS)
SCHEMA["properties"]["physics"]["properties"]["joints"]["enum"] = list(JOINT_LAWS)


def _with_defaults(cls):
    """A validator that fills in the schema's defaults while validating
    (the jsonschema FAQ recipe)."""
    validate_props = cls.VALIDATORS["properties"]

    def set_defaults(validator, properties, instance, schema):
        if isinstance(instance, dict):
            for key, sub in properties.items():
                if "default" in sub and key not in instance:
                    instance[key] = copy.deepcopy(sub["default"])
        yield from validate_props(validator, properties, instance, schema)

    return validators.extend(cls, {"properties": set_defaults})


_Validator = _with_defaults(Draft202012Validator)


def _path(error):
    return ".".join(str(p) for p in error.absolute_path) or "scene"


def validate_scene(scene):
    """Fills defaults in place and checks the scene; raises InputError naming
    the first offending field."""
    if not isinstance(scene, dict):
        raise InputError("scene", "must be a mapping")
    errors = sorted(_Validator(SCHEMA).iter_errors(scene), key=lambda e: list(e.absolute_path))
    if errors:
        e = errors[0]
        raise InputError(_path(e), e.message)
    phys = scene["physics"]
    if phys["displacements"] == "large" and phys["blocks"] != "rigid":
        raise InputError("physics.displacements", "large displacements need rigid blocks: deformable blocks "
                         f"({phys['blocks']}) are small-displacement (strains on the initial geometry)")
    if phys["blocks"] == "rigid" and scene["outputs"]["state"]:
        raise InputError("outputs.state", "the final state (VTK: zones and their damage) exists for deformable "
                         "blocks only, not for rigid ones")
    g = scene["geometry"]
    if BLOCK_MODELS[phys["blocks"]].material is MohrCoulomb:
        reason = crack_band_error(g, scene["numerics"]["cells"][0])
        if reason:
            raise InputError("numerics.cells.0", reason)
    n_units = g["courses"] * g["units_per_course"]
    n_joints = len(running_bond_joints(g["courses"], g["units_per_course"]))
    for key, n, what in (("per_unit", n_units, "units"), ("per_joint", n_joints, "joints")):
        for name, values in scene["materials"].get(key, {}).items():
            if isinstance(values, list) and len(values) != n:
                raise InputError(f"materials.{key}.{name}",
                                 f"needs one value per {what[:-1]} ({n} {what}), got {len(values)}")
    test = scene["loading"]["test"]
    if test == "bending":
        length = wall_length(g)
        bend = scene["loading"]["bending"]
        for key in ("supports_x", "loads_x"):
            for i, x in enumerate(bend[key]):
                if not (0.5 * bend["strip_width"] <= x <= length - 0.5 * bend["strip_width"]):
                    raise InputError(f"loading.bending.{key}.{i}",
                                     f"{x} m is outside the wall (0 to {length:.4g} m)")
    if test == "triplet":
        for key, want in (("courses", 3), ("units_per_course", 1)):
            if g[key] != want:
                raise InputError(f"geometry.{key}", f"a triplet test has {want} (three units stacked), got {g[key]}")
    return scene


def _set(scene, dotted, value):
    keys = dotted.split(".")
    node = scene
    for k in keys[:-1]:
        if not isinstance(node, dict):
            raise InputError(dotted, f"{k!r} is not a section")
        node = node.setdefault(k, {})
    node[keys[-1]] = value


def apply_overrides(scene, overrides):
    """``overrides``: strings 'path.to.key=value' (value parsed as YAML)."""
    for item in overrides or ():
        if "=" not in item:
            raise InputError("--set", f"expected path.to.key=value, got {item!r}")
        key, raw = item.split("=", 1)
        _set(scene, key.strip(), read_yaml(raw))
    return scene


def load_scene(path, overrides=()):
    try:
        with open(path) as f:
            scene = read_yaml(f.read())
    except OSError as e:
        raise InputError("scene", f"cannot read {path}: {e.strerror}") from None
    except yaml.YAMLError as e:
        raise InputError("scene", f"{path} is not valid YAML: {e}") from None
    return validate_scene(apply_overrides(scene, overrides))
