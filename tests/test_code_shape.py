"""The package's shape: no module over 400 lines, no
function over 20 parameters; outside the kernels no function over 60
lines and no class over 200; only the solver and its history read the
step kernel's history columns by index."""
import ast
import re
from pathlib import Path

import masonrydem

SRC = Path(masonrydem.__file__).parent


def _modules():
    return sorted(p for p in SRC.rglob("*.py") if "__pycache__" not in p.parts)


def _name(p):
    return p.relative_to(SRC).as_posix()


def test_no_module_over_400_lines():
    long = {_name(p): n for p in _modules() if (n := len(p.read_text().splitlines())) > 400}
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


def test_short_functions_and_classes_outside_the_kernels():
    """The kernels' loops stay whole (a split costs a call per step);
    everything else reads in one screen."""
    long = []
    for p in _modules():
        if _name(p).startswith("dem/kernels/"):
            continue
        for node in ast.walk(ast.parse(p.read_text())):
            limit = 60 if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) else \
                200 if isinstance(node, ast.ClassDef) else None
            if limit and node.end_lineno - node.lineno + 1 > limit:
                long.append(f"{_name(p)}:{node.lineno} {node.name} ({node.end_lineno - node.lineno + 1} lines)")
    assert not long


def test_history_columns_are_read_by_name():
    """The kernel's history rows (kernels.layout H_*, h_force, h_disp) are
    turned into named columns in one place (history.from_kernel, the
    solver's advance that fills them, and the batch that tells a lane's
    finite steps); everything else reads the names."""
    pattern = re.compile(r"\b(H_STEP|H_RATIO|H_KE|H_MON|h_force|h_disp)\b")
    readers = {_name(p) for p in _modules() if pattern.search(p.read_text())}
    assert readers <= {"dem/history.py", "dem/solver.py", "dem/batch.py"} | {_name(p) for p in _modules()
                                                             if _name(p).startswith("dem/kernels/")}
