"""`make mutants` (benchmarks/mutants.py) cannot rot unseen: every seeded
fault's text is still once in its module, so that the full run applies
each one; the faulted module is still Python, so that a fault is caught
by a test and not by a syntax error; and every module with a fault names
the tests that guard it, which exist."""
import ast
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
import mutants  # noqa: E402


def test_every_fault_still_applies_once():
    assert mutants.stale(mutants.FAULTS) == []


@pytest.mark.parametrize("name, module, old, new", mutants.FAULTS, ids=[f[0] for f in mutants.FAULTS])
def test_each_fault_changes_its_module_into_valid_python(name, module, old, new):
    text = (mutants.SRC / module).read_text()
    assert old != new
    ast.parse(text.replace(old, new))


def test_every_faulted_module_has_guards_that_exist():
    names = [f[0] for f in mutants.FAULTS]
    assert len(names) == len(set(names)), "two faults share a name"
    for module in {f[1] for f in mutants.FAULTS}:
        files = [a for a in mutants.GUARDS[module] if a.endswith(".py")]
        assert files and all((ROOT / "tests" / f).is_file() for f in files), module
