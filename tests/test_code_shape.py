"""The package's shape (issue 21): no module over 500 lines, no function
over 20 parameters."""
import ast
from pathlib import Path

import masonrydem

SRC = Path(masonrydem.__file__).parent


def _modules():
    return sorted(p for p in SRC.rglob("*.py") if "__pycache__" not in p.parts)


def test_no_module_over_500_lines():
    long = {p.relative_to(SRC).as_posix(): n for p in _modules() if (n := len(p.read_text().splitlines())) > 500}
    assert not long


def test_no_function_over_20_parameters():
    wide = []
    for p in _modules():
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                a = node.args
                n = len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + bool(a.vararg) + bool(a.kwarg)
                if n > 20:
                    wide.append(f"{p.name}:{node.lineno} {getattr(node, 'name', 'lambda')} ({n})")
    assert not wide
