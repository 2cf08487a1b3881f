"""The package's version and the solver's source hash: which source files
decide what a simulation computes (SIMULATION), and a hash of what they
compute (``source_hash``), which every simulation's row records and every
simulation rule of the workflow takes as a parameter.  Imports nothing of
the package: any layer may read it."""
import ast
import hashlib
import json
import os
from pathlib import Path

import yaml

__version__ = "0.1.0"

# the folders and modules whose sources decide what a simulation computes
SIMULATION = ("errors.py", "scene", "dem", "specimen")


def simulation_sources():
    """The package's files that decide what a simulation computes: every
    module and data file in the folders and modules of SIMULATION."""
    here = Path(__file__).parent
    out = []
    for item in SIMULATION:
        path = here / item
        files = [path] if path.is_file() else path.rglob("*")
        out += [p.relative_to(here).as_posix() for p in files
                if p.suffix in (".py", ".yaml") and "__pycache__" not in p.parts]
    return sorted(out)


def source_code(name, text):
    """What a source file computes, without its documentation: a Python
    module's syntax tree without docstrings (comments and layout are not in
    the tree), a YAML file's data without its 'description' texts."""
    if name.endswith(".py"):
        tree = ast.parse(text)
        for node in ast.walk(tree):
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body \
                    and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant) \
                    and isinstance(node.body[0].value.value, str):
                node.body = node.body[1:] or [ast.Pass()]
        return ast.dump(tree)

    def data(x):
        if isinstance(x, dict):
            return {k: data(v) for k, v in x.items() if not (k == "description" and isinstance(v, str))}
        return [data(v) for v in x] if isinstance(x, list) else x
    return json.dumps(data(yaml.safe_load(text)), sort_keys=True)


def source_hash():
    """Hash of what the source files that decide a simulation compute (the
    workflow passes it as a parameter of every simulation rule, so that a
    solver change reruns them, and a change to the analysis, the figures or
    any documentation, docstrings and comments included, does not).

    Parsing the sources takes about 0.4 s, a good part of a study job's
    start-up: the result is kept in __pycache__/source_hash.json under the
    hash of the files' bytes (milliseconds), and recomputed when they
    change."""
    here = Path(__file__).parent
    names = simulation_sources()
    texts = {name: (here / name).read_bytes() for name in names}
    raw = hashlib.sha256(b"".join(name.encode() + b"\0" + texts[name] for name in names)).hexdigest()
    cache = here / "__pycache__" / "source_hash.json"
    try:
        known = json.loads(cache.read_text())
        if known.get("raw") == raw:
            return known["hash"]
    except (OSError, ValueError, AttributeError):
        pass
    h = hashlib.sha256()
    for name in names:
        h.update(name.encode())
        h.update(source_code(name, texts[name].decode("utf-8")).encode())
    value = h.hexdigest()[:12]
    try:
        cache.parent.mkdir(exist_ok=True)
        tmp = cache.with_name(f".{cache.name}.{os.getpid()}")
        tmp.write_text(json.dumps({"raw": raw, "hash": value}))
        os.replace(tmp, cache)
    except OSError:       # a read-only installation: recomputed each time
        pass
    return value

