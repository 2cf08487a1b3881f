"""masonrydem: a discrete element solver for masonry micro-models
(deformable or rigid blocks, zero-thickness joints, explicit quasi-static
dynamic relaxation) and stochastic studies of masonry wallettes on it.

The package is in layers, each a folder that imports only from the
layers below it (docs/architecture.md; pyproject.toml states the contract
and `make test` checks it):

    cli        the command line
    pipeline   what a workflow runs: the runs of each stage, checks at planning
    report     captions, figures, pictures
    analysis   statistics, equations, sensitivity, fractiles, predict, validation
    study      a study file, its sampling and its samples' settings
    specimen   one wallette test: scene, masonry rules, protocol, the result row
    dem        the solver: model, laws, assembly, kernels, integration
    errors     bad input

What a simulation computes is decided by ``dem``, ``specimen`` and
``errors`` alone: their sources make the solver's hash (``source_hash``).
"""
__version__ = "0.1.0"

# the folders and modules whose sources decide what a simulation computes
SIMULATION = ("errors.py", "dem", "specimen")
_EXPORTS = {"InputError": "errors", "Model": "dem.model", "Elastic": "dem.laws", "MohrCoulomb": "dem.laws",
            "JointProps": "dem.laws"}


def __getattr__(name):
    """The solver's main classes on first use (masonrydem.Model): importing
    the package alone loads no numerical code."""
    if name in _EXPORTS:
        import importlib
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def simulation_sources():
    """The package's files that decide what a simulation computes: every
    module and data file in the folders and modules of SIMULATION."""
    from pathlib import Path
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
        import ast
        tree = ast.parse(text)
        for node in ast.walk(tree):
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body \
                    and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant) \
                    and isinstance(node.body[0].value.value, str):
                node.body = node.body[1:] or [ast.Pass()]
        return ast.dump(tree)
    import json

    import yaml

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
    import hashlib
    import json
    import os
    from pathlib import Path
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


__all__ = ["Elastic", "InputError", "JointProps", "Model", "MohrCoulomb", "__version__", "source_hash"]
