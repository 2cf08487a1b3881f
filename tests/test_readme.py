"""The README's commands work as written (issue 24).  The cheap ones run:
its Python example, its first `masonrydem run` (the study's reference
wallette), and every Snakemake command in it as a dry run; the smoke run
and the report command run in tests/test_workflow.py."""
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def _commands(program):
    """The README's commands that start with .venv/bin/PROGRAM, in code
    blocks (backslash continuations joined) and in inline code spans."""
    blocks = re.findall(r"```\n(.*?)```", README, re.S)
    lines = [x.split("#")[0].strip() for b in blocks for x in b.replace("\\\n", " ").splitlines()]
    spans = [" ".join(x.split()) for x in re.findall(r"`([^`]+)`", re.sub(r"```.*?```", "", README, flags=re.S))]
    return [shlex.split(c) for c in lines + spans if c.startswith(f".venv/bin/{program} ")]


def test_python_example_runs():
    code = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.split()[-1] == "converged"


def test_first_masonrydem_run_gives_the_studys_reference(tmp_path):
    """`masonrydem run config/scenes/willis.yaml --out runs/ref` (output
    folder moved to a temporary one): what the scene file says is what the
    study runs, so its P_max and steps are those of the workflow's
    reference run (results/validation/summary.csv, reference at 0 MPa)."""
    cmd = _commands("masonrydem")[0]
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
    from masonrydem.specimen.scene import build_scene
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


def _setting(label):
    """The accuracy study's setting of a README row: 'the defaults' is the
    row 'default'; else the unit model, cells and refinement make its name
    (potential-crack 4x3x2 head joints: pc_c4x3x2_head; none: _r1;
    "damping 0.8": _d08; "at half the rate": _half, "at 1.5 times the
    rate": _rate15; elasto-plastic 9x4x3, none: ep_c9x4x3)."""
    if "**the defaults**" in label:
        return "default"
    head = label.split("(")[0]
    model, cells, refined = (x.strip() for x in head.split(",")[:3])
    if model == "elasto-plastic":
        return f"ep_c{cells}"
    damping = "_d08" if "damping 0.8" in head else ""
    rate = "_half" if "half the rate" in head else "_rate15" if "1.5 times the rate" in head else ""
    return f"pc_c{cells}_" + ("head" if refined == "head joints" else "r1") + damping + rate


def test_the_accuracy_table_is_the_committed_study():
    """The README's "What accuracy costs" table states what
    results/accuracy/runs.csv holds: per row the largest error of P_max
    (by its size, with its sign, in %) in each mode's cases, and the mean
    run time over the five cases (a decimal below 10 s).  A rerun of the accuracy study that is
    not carried into the README fails here."""
    section = README[README.index("## What accuracy costs"):]
    rows = [r.strip("|").split("|") for r in section.split("\n\n")[2].splitlines()[2:]]
    runs = pd.read_csv(ROOT / "results/accuracy/runs.csv")
    assert rows
    for label, *errors, time in rows:
        g = runs[runs.setting == _setting(label)].set_index("case")
        assert len(g) == 5, label
        for mode, shown in zip(("joint", "brick", "mixed"), errors):
            e = 100 * g[g.index.str.startswith(mode)].error
            largest = e[e.abs().idxmax()]
            assert shown.strip() == f"{largest:+.1f} %", (label, mode, largest)
        t = g.wall_time_s.mean()
        assert time.strip() == (f"{t:.1f} s" if t < 10 else f"{t:.0f} s"), (label, t)
