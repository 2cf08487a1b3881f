"""Scenes: a specimen described in YAML, validated before anything runs
(specimen.py builds it into a Model).

A scene (schema: scene_schema.yaml, defaults = the Willis wallette of
docs/study.md) declares geometry, physics, materials, loading, numerics and
outputs.  ``load_scene`` reads it, applies ``--set`` overrides and checks it;
every error names the field (a dotted path, as the scene writes it) and the
reason.  Refused before anything is allocated: a file that is not UTF-8
text or not YAML, a key given twice, an alias bomb, a NaN or an infinity, a
value the schema does not allow, a test whose geometry makes no sense, and
a model too large for the machine's memory (``model_size``).
"""
import copy
import os
import re
from dataclasses import dataclass
from importlib import resources

import numpy as np
import yaml
from jsonschema import Draft202012Validator, validators

from .errors import InputError, check_finite
from .laws import BLOCK_MODELS, JOINT_LAWS, Elastic, MohrCoulomb
from .blocks import refine_axes
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


MAX_BYTES = 1_000_000     # a scene file (a scene is a few kB)
MAX_VALUES = 100_000      # values in a document once its aliases are expanded


def read_yaml(text, where="scene"):
    """YAML ``text`` (a scene, a ``--set`` value named ``where``), refusing a
    key given twice in a mapping (YAML keeps the last one silently), an
    alias to itself, and more than MAX_VALUES values once aliases are
    expanded (an alias bomb: a few lines that expand to billions), before
    anything is built from it."""
    loader = _Loader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        _check_node(node, "" if where == "scene" else where, {})
        return loader.construct_document(node)
    except RecursionError:
        raise InputError(where, "is nested too deeply") from None
    finally:
        loader.dispose()


def _check_node(node, path, seen):
    """The number of values under a YAML node, aliases expanded (each
    distinct node counted once: linear in the document's own size)."""
    if id(node) in seen:
        if seen[id(node)] is None:
            raise InputError(path or "scene", "refers to itself (a recursive YAML alias)")
        return seen[id(node)]
    seen[id(node)] = None
    n = 1
    if isinstance(node, yaml.MappingNode):
        lines = {}
        for k, v in node.value:
            name = k.value if isinstance(k, yaml.ScalarNode) else "?"
            sub = f"{path}.{name}" if path else name
            if name in lines and k.tag != "tag:yaml.org,2002:merge":
                raise InputError(sub, f"is given twice (lines {lines[name]} and {k.start_mark.line + 1}): "
                                      "keep one")
            lines[name] = k.start_mark.line + 1
            n += _check_node(k, sub, seen) + _check_node(v, sub, seen)
    elif isinstance(node, yaml.SequenceNode):
        n += sum(_check_node(v, f"{path}.{i}" if path else str(i), seen) for i, v in enumerate(node.value))
    if n > MAX_VALUES:
        raise InputError(path or "scene", f"holds more than {MAX_VALUES} values once its YAML aliases are "
                                          "expanded (an alias bomb?)")
    seen[id(node)] = n
    return n


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
    check_finite(scene)
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
    _check_size(scene)      # before anything that takes time in proportion to the model's size
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
        _check_four_point(bend["supports_x"], bend["loads_x"])
    if test == "triplet":
        for key, want in (("courses", 3), ("units_per_course", 1)):
            if g[key] != want:
                raise InputError(f"geometry.{key}", f"a triplet test has {want} (three units stacked), got {g[key]}")
    return scene


def _check_four_point(supports, loads):
    """Four-point bending: the loads between the outer supports, no support
    between the loads (else the moment between the loads is not P a / 2,
    and the strength computed from it means nothing)."""
    for i, x in enumerate(loads):
        if not min(supports) < x < max(supports):
            raise InputError(f"loading.bending.loads_x.{i}", f"{x} m is not between the supports "
                             f"(loading.bending.supports_x: {min(supports)} to {max(supports)} m)")
    for i, x in enumerate(supports):
        if min(loads) <= x <= max(loads):
            raise InputError(f"loading.bending.supports_x.{i}", f"{x} m lies between the loads "
                             f"(loading.bending.loads_x: {min(loads)} to {max(loads)} m); the supports must "
                             "lie outside them")


# bytes per item of a model at the peak of building it and setting up its
# solver, measured on the wallette and rounded up (9 x 4 x 3 cells: 25,920
# tetrahedra and 7,119 sub-contacts, 80 MB; rigid units at refine 4: 29,597
# sub-contacts, 34 MB; potential-crack hex8i 4 x 4 x 3, refine 2: 1,152
# cells and 14,637 sub-contacts, 17 MB)
ITEM_BYTES = dict(nodes=500, tetrahedra=3000, cells=5000, sub_contacts=1500)


def model_size(scene):
    """An upper estimate of the model a validated scene builds, from its
    numbers alone (nothing allocated): nodes, tetrahedra (zones), linear
    cells, sub-contacts (joints, crack interfaces and strips: composite
    Simpson points, 2 r + 1 per interval and direction at refine r) and
    bytes (ITEM_BYTES)."""
    g, num = scene["geometry"], scene["numerics"]
    model = BLOCK_MODELS[scene["physics"]["blocks"]]
    units = g["courses"] * g["units_per_course"]
    from .specimen import refine_by_kind
    r = {k: refine_axes(v) for k, v in refine_by_kind(num["subcontact_refine"]).items()}
    pieces = 2 if model.crack_interface else 1
    a, b, c = max(num["cells"][0], pieces), num["cells"][1], num["cells"][2]

    def simpson(m, rm, n, rn):      # points on a face of m x n intervals, refined rm and rn times
        return (2 * rm * m + 1) * (2 * rn * n + 1)

    bend = scene["loading"]["bending"]
    strips = len(bend["supports_x"]) + len(bend["loads_x"]) if scene["loading"]["test"] == "bending" else 0
    # per unit a head joint (and its crack interface) and a bed joint on the
    # union of two face grids, offset by the bond (their lines coincide when
    # the offset falls on a grid line); strips across the wall's height, a
    # few cells wide
    shift = g["bond_offset"] * a
    along = a if abs(shift - round(shift)) < 1e-9 else 2 * a
    # faces normal to x: (y, z); to z: (x, y); the strips' (normal to y): (z, x)
    face = {k: {0: (v[1], v[2]), 2: (v[0], v[1]), 1: (v[2], v[0])} for k, v in r.items()}
    subs = (units * (simpson(b, face["head"][0][0], c, face["head"][0][1])
                     + (pieces - 1) * simpson(b, face["crack"][0][0], c, face["crack"][0][1])
                     + simpson(along, face["bed"][2][0], b, face["bed"][2][1]))
            + strips * simpson(g["courses"] * c, face["strips"][1][0], 3, face["strips"][1][1]))
    hexes = 0 if model.rigid else units * a * b * c
    zones = model.material is not Elastic or num["elastic_element"] == "zones"
    size = dict(nodes=strips + units * (pieces if model.rigid else (a + pieces) * (b + 1) * (c + 1)),
                tetrahedra=10 * hexes if zones else 0, cells=0 if zones else hexes, sub_contacts=subs)
    size["bytes"] = sum(ITEM_BYTES[k] * n for k, n in size.items())
    return size


def memory_bytes():
    """The machine's physical memory, or None if unknown."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None


def _check_size(scene):
    """Refuses a model that would not fit in the machine's memory (it would
    end in a MemoryError after seconds or minutes of building), naming the
    setting to blame: the wall if it is too large at the schema's default
    cells and refinement, else the cells if too many at refinement 1, else
    the refinement."""
    memory = memory_bytes()
    if memory is None or model_size(scene)["bytes"] <= memory:
        return
    g, num = scene["geometry"], scene["numerics"]
    defaults = {k: v["default"] for k, v in SCHEMA["properties"]["numerics"]["properties"].items()}

    def fits(**numerics):
        return model_size({**scene, "numerics": {**num, **numerics}})["bytes"] <= memory

    if not fits(cells=defaults["cells"], subcontact_refine=defaults["subcontact_refine"]):
        field = "geometry.courses" if g["courses"] >= g["units_per_course"] else "geometry.units_per_course"
    else:
        field = "numerics.subcontact_refine" if fits(subcontact_refine=1) else "numerics.cells"
    size = model_size(scene)
    raise InputError(field, f"the model would need an estimated {_big(size['bytes'], 1e9)} GB of memory, more "
                     f"than this machine's {memory / 1e9:.3g} GB: {_big(size['tetrahedra'])} tetrahedra, "
                     f"{_big(size['cells'])} linear cells and {_big(size['sub_contacts'])} sub-contacts for "
                     f"{_big(g['courses'] * g['units_per_course'])} units (geometry.courses {g['courses']} x "
                     f"geometry.units_per_course {g['units_per_course']}) at numerics.cells {num['cells']} and "
                     f"numerics.subcontact_refine {num['subcontact_refine']}; use fewer cells, a lower refinement or "
                     "a smaller wall")


def _big(n, unit=1):
    return f"{n / unit:.3g}" if n < 10 ** 300 else f"over {1e300 / unit:.3g}"


def _set(scene, dotted, value):
    keys = dotted.split(".")
    if not all(k.strip() for k in keys):
        raise InputError("--set", f"{dotted!r} is not a dotted path of settings (e.g. materials.units.E)")
    node = scene
    for i, k in enumerate(keys[:-1]):
        node = node.setdefault(k, {})
        if not isinstance(node, dict):
            raise InputError(dotted, f"{'.'.join(keys[:i + 1])} is a value ({node!r}), not a section of "
                             f"settings: it has no {keys[i + 1]!r}")
    node[keys[-1]] = value


def apply_overrides(scene, overrides):
    """``overrides``: strings 'path.to.key=value' (value parsed as YAML)."""
    if not isinstance(scene, dict):
        raise InputError("scene", "must be a mapping")
    for item in overrides or ():
        if "=" not in item:
            raise InputError("--set", f"expected path.to.key=value, got {item!r}")
        key, raw = (x.strip() for x in item.split("=", 1))
        try:
            value = read_yaml(raw, key)
        except yaml.YAMLError as e:
            raise InputError(key, f"the value {raw!r} is not valid YAML: {e}") from None
        _set(scene, key, value)
    return scene


def read_scene(path):
    """The scene file at ``path`` parsed (UTF-8 YAML), not yet validated."""
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_BYTES + 1)
    except OSError as e:
        raise InputError("scene", f"cannot read {path}: {e.strerror}") from None
    if len(data) > MAX_BYTES:
        raise InputError("scene", f"{path} is larger than {MAX_BYTES} bytes: not a scene (a scene is a few kB)")
    try:
        scene = read_yaml(data.decode("utf-8"))
    except UnicodeDecodeError as e:
        line = data[:e.start].count(b"\n") + 1
        raise InputError("scene", f"{path} is not UTF-8 text (line {line}: byte 0x{data[e.start]:02x}): a scene is "
                         "a YAML text file in UTF-8") from None
    except yaml.YAMLError as e:
        raise InputError("scene", f"{path} is not valid YAML: {e}") from None
    if not isinstance(scene, dict):
        raise InputError("scene", f"{path} must hold a mapping of settings (name, geometry, ...), "
                         f"not {type(scene).__name__}")
    return scene


def load_scene(path, overrides=()):
    """The scene file at ``path`` with ``overrides`` ('path.to.key=value'),
    validated; InputError names the first offending field."""
    return validate_scene(apply_overrides(read_scene(path), overrides))
