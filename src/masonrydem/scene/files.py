"""Reading a scene: its YAML file and the ``--set`` overrides, each
refused before anything is built when it is malformed (not UTF-8 text or
not YAML, a key given twice, an alias bomb), naming the setting as the
file or the command line writes it.  typed.py validates what this reads."""
import re

import yaml

from ..errors import InputError


class _Loader(getattr(yaml, "CSafeLoader", yaml.SafeLoader)):
    """YAML loader that also reads 15e9 or 0.3e6 as floats (YAML 1.1, and so
    PyYAML, wants 15.0e+9).  LibYAML's parser where PyYAML has it (the
    scene schema loads in a tenth of the time; the same documents)."""


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
    except yaml.YAMLError as e:     # LibYAML's own limit on nesting
        if "flow level" not in str(e) and "block level" not in str(e):
            raise
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


def set_value(scene, dotted, value):
    """Sets the setting at the dotted path ``dotted`` of the scene mapping
    (sections created as needed)."""
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
        set_value(scene, key, value)
    return scene


def read_scene(path, what="scene"):
    """The scene file (or, ``what`` 'study', the study file) at ``path``
    parsed (UTF-8 YAML), not yet validated; errors name ``what``."""
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_BYTES + 1)
    except OSError as e:
        raise InputError(what, f"cannot read {path}: {e.strerror}") from None
    if len(data) > MAX_BYTES:
        raise InputError(what, f"{path} is larger than {MAX_BYTES} bytes: not a {what} file (one is a few kB)")
    try:
        scene = read_yaml(data.decode("utf-8"), what)
    except UnicodeDecodeError as e:
        line = data[:e.start].count(b"\n") + 1
        raise InputError(what, f"{path} is not UTF-8 text (line {line}: byte 0x{data[e.start]:02x}): a {what} "
                         "file is YAML text in UTF-8") from None
    except yaml.YAMLError as e:
        raise InputError(what, f"{path} is not valid YAML: {e}") from None
    if not isinstance(scene, dict):
        raise InputError(what, f"{path} must hold a mapping of settings (name, ...), "
                         f"not {type(scene).__name__}")
    return scene
