"""What decides a workflow step's outputs besides its inputs and settings:
its code.  Snakemake does not follow a script's imports, so each script
rule carries, as a parameter, the fingerprint of the script and of every
module of the package it imports, directly or through others
(``code_fingerprint``).  The solver and the specimen (dem/, specimen/)
stand in it as one item, the solver's source hash (sources.py: their
sources and those of scene/ and errors.py), so that a step that runs or
reads simulations reruns when the solver changes; a step whose imports
reach only the scene (the sampling) carries the scene's own code, and
does not rerun when the solver changes.
"""
import ast
import functools
import hashlib
import json
from pathlib import Path

from .. import sources

PACKAGE = Path(sources.__file__).parent
# the folders that stand in a fingerprint as the solver's source hash
SOLVER = ("dem", "specimen")


def _digest(*items):
    return hashlib.sha256(json.dumps(items, sort_keys=True, default=str).encode()).hexdigest()[:16]


def module_file(name):
    """The source file of the package's module ``name`` (dotted, without
    'masonrydem.'; '' the package itself), or None if there is none."""
    base = PACKAGE.joinpath(*name.split(".")) if name else PACKAGE
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file():
            return path
    return None


def _name_of(path):
    """The dotted name (without 'masonrydem.') of a package source file."""
    rel = path.relative_to(PACKAGE).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


def imports(text, package=None):
    """The package's modules a source imports, by dotted name without
    'masonrydem.': absolute imports of masonrydem, and relative ones from
    within the package's module ``package`` (its dotted package name);
    ``from X import y`` counts X.y where that is a module, else X."""
    found = set()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                if package is None:
                    continue
                parts = package.split(".") if package else []
                parts = parts[:len(parts) - (node.level - 1)] if node.level > 1 else parts
                base = ".".join(parts + ([node.module] if node.module else []))
            elif (node.module or "").split(".")[0] == "masonrydem":
                base = node.module.removeprefix("masonrydem").lstrip(".")
            else:
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}" if base else alias.name
                found.add(sub if module_file(sub) else base)
        elif isinstance(node, ast.Import):
            found |= {a.name.removeprefix("masonrydem").lstrip(".") for a in node.names
                      if a.name.split(".")[0] == "masonrydem"}
    return {n for n in found if module_file(n)}


@functools.cache
def _module_imports(name):
    path = module_file(name)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    return frozenset(imports(path.read_text(), package))


def _with_parents(name):
    """A module and the packages above it (importing it runs their __init__)."""
    parts = name.split(".") if name else []
    return {".".join(parts[:k]) for k in range(len(parts) + 1)}


@functools.cache
def modules_used(name):
    """A package module and every package module importing it runs,
    transitively (the packages' __init__ included)."""
    found, todo = set(), _with_parents(name)
    while todo:
        n = todo.pop()
        found.add(n)
        todo |= set().union(*(_with_parents(m) for m in _module_imports(n))) - found
    return frozenset(found)


def simulation_module(name):
    """Whether a module stands in a fingerprint as the solver's hash."""
    return name.split(".")[0] in SOLVER


@functools.cache
def _module_code(name):
    path = module_file(name)
    return sources.source_code(path.name, path.read_text())


def script_modules(script):
    """The package's modules a script uses (``modules_used`` of each it
    imports), the package itself ('') included."""
    return set().union(*(modules_used(m) for m in imports(Path(script).read_text())), {""})


def code_fingerprint(script):
    """The fingerprint of a script and the package modules it uses
    (docstrings and comments aside): each module's code, the simulation's
    modules as the solver's source hash."""
    used = script_modules(script)
    own = sorted(n for n in used if n and not simulation_module(n))
    solver = sources.source_hash() if any(simulation_module(n) for n in used if n) else None
    return _digest(sources.source_code(Path(script).name, Path(script).read_text()),
                   *((n, _module_code(n)) for n in own), solver)
