"""masonrydem: a discrete element solver for masonry micro-models
(deformable or rigid blocks, zero-thickness joints, explicit quasi-static
dynamic relaxation); docs/formulation.md describes it."""
from .errors import InputError
from .laws import Elastic, JointProps, MohrCoulomb
from .model import Model

__version__ = "0.1.0"

# A module that does not decide what a simulation computes (the analysis of
# results, figures, the workflow's planning) says so itself, with a line
# 'ANALYSIS_ONLY = True' (a data file: '# ANALYSIS_ONLY = True'): a new one
# is then left out of the source hash without a change here.
_MARKS = {".py": b"\nANALYSIS_ONLY = True", ".yaml": b"\n# ANALYSIS_ONLY = True"}


def __getattr__(name):
    """masonrydem.ANALYSIS_ONLY: the names of the files marked analysis-only."""
    if name == "ANALYSIS_ONLY":
        from pathlib import Path
        return tuple(sorted(p.name for p in Path(__file__).parent.iterdir()
                            if p.suffix in _MARKS and _MARKS[p.suffix] in p.read_bytes()))
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def simulation_sources():
    """The package's files that decide what a simulation computes: every
    module and data file but the analysis-only ones (ANALYSIS_ONLY; a new
    module counts unless it says it is one)."""
    from pathlib import Path
    here = Path(__file__).parent
    skip = set(__getattr__("ANALYSIS_ONLY"))
    return sorted(p.relative_to(here).as_posix() for p in here.rglob("*")
                  if p.suffix in (".py", ".yaml") and p.name not in skip and "__pycache__" not in p.parts)


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
