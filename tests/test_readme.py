"""The commands of the README and of the usage page it points to
(docs/usage.md) work as written.  The cheap ones run: the Python example,
the first `masonrydem run` (the study's reference wallette), and every
Snakemake command as a dry run; the smoke run and the report command run in
tests/test_workflow.py.  The numbers the docs quote: tests/test_docs_numbers.py."""
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
# the README and the page its command-line section points to, read as one
TEXT = README + "\n" + (ROOT / "docs" / "usage.md").read_text()


def _commands(program):
    """The commands of the README and docs/usage.md that start with
    .venv/bin/PROGRAM, in code blocks (backslash continuations joined) and in
    inline code spans."""
    blocks = re.findall(r"```\n(.*?)```", TEXT, re.S)
    lines = [x.split("#")[0].strip() for b in blocks for x in b.replace("\\\n", " ").splitlines()]
    spans = [" ".join(x.split()) for x in re.findall(r"`([^`]+)`", re.sub(r"```.*?```", "", TEXT, flags=re.S))]
    return [shlex.split(c) for c in lines + spans if c.startswith(f".venv/bin/{program} ")]


def test_python_example_runs():
    code = re.search(r"```python\n(.*?)```", TEXT, re.S).group(1)
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.split()[-1] == "converged"


def test_first_masonrydem_run_gives_the_studys_reference(tmp_path):
    """`masonrydem run config/scenes/willis.yaml --out runs/ref` (output
    folder moved to a temporary one): what the scene file says is what the
    study runs, so its P_max and steps are those of the workflow's
    reference run (results/validation/summary.csv, reference at 0 MPa)."""
    cmd = next(c for c in _commands("masonrydem") if c[1] == "run")
    assert cmd[1:3] == ["run", "config/scenes/willis.yaml"] and "--set" not in cmd
    cmd[cmd.index("--out") + 1] = str(tmp_path / "ref")
    r = subprocess.run([sys.executable, "-m", "masonrydem.cli", *cmd[1:], "--quiet"], cwd=ROOT, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    row = pd.read_parquet(tmp_path / "ref" / "result.parquet").iloc[0]
    ref = pd.read_csv(ROOT / "results/validation/summary.csv").set_index("run").loc["reference_sv0.0"]
    assert float(f"{row['P_max_kN']:.5g}") == ref["P_max_kN"] and row["steps"] == ref["steps"]
    # and a strength a wallette of these materials can have: above its
    # joints' tensile strength (a bed joint's alone, cracking in bending)
    # and below its units' (sigma = 6 M / (b h^2) of the units themselves)
    from masonrydem.scene import build_scene
    mat = build_scene(ROOT / "config/scenes/willis.yaml").materials
    assert float(mat.joints.ft.mean()) < row["strength_mpa"] * 1e6 < float(mat.units.ft.mean())


SNAKEMAKE = _commands("snakemake")


@pytest.mark.parametrize("cmd", [c for c in SNAKEMAKE if not {"--report", "--unlock", "--profile"} & set(c)],
                         ids=" ".join)
def test_snakemake_commands_plan(cmd):
    """Each Snakemake command of the README plans as written (dry run:
    nothing runs, nothing is written under results/).  The report command
    runs in tests/test_workflow.py, the cluster profile's plan there too."""
    r = subprocess.run([sys.executable, "-m", "snakemake", *cmd[1:], "-n", "--quiet", "rules"], cwd=ROOT,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]


def test_the_readme_names_its_commands():
    """The commands above are found (a README rewritten without them would
    make those tests vacuous)."""
    assert len(SNAKEMAKE) >= 6 and _commands("masonrydem")


@pytest.mark.parametrize("cmd", [c for c in _commands("masonrydem") if c[1] in ("check", "predict")], ids=" ".join)
def test_check_and_predict_commands_work(cmd):
    """The README's `masonrydem check` and `masonrydem predict` commands run
    as written and exit 0, printing what they report (a model's size; the
    governing failure mode)."""
    r = subprocess.run([sys.executable, "-m", "masonrydem.cli", *cmd[1:]], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert ("governing" if cmd[1] == "predict" else "valid") in r.stdout, r.stdout[-2000:]
