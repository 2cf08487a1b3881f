"""The numbers the README and docs/ quote against the tables and the config
they come from.  Each test reads the number as the text states it and the
true one from its source (results/**.csv, config/*.yaml, the scene schema,
the package's sources), so that a rerun or a changed setting not carried
into the docs fails here.  Measured times live in one place, the README's
set-up table; the performance log (docs/dev/) and CHANGELOG.md are history
and are not checked.  Fast: no simulation, no import of the solver."""
import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
# the pages that state the current truth (the performance log is history)
DOCS = {p.relative_to(ROOT).as_posix(): p.read_text() for p in sorted((ROOT / "docs").glob("*.md"))}
PAGES = {"README.md": README, **DOCS}
CONFIG = yaml.safe_load((ROOT / "config/config.yaml").read_text())
STUDY = yaml.safe_load((ROOT / CONFIG["study"]["file"]).read_text())
SCHEMA = yaml.safe_load((ROOT / "src/masonrydem/scene/schema.yaml").read_text())
RESULTS = ROOT / "results"


def _flat(text):
    """The text with its line breaks as spaces (a number and its unit may
    sit on two lines)."""
    return " ".join(text.split())


def _section(text, heading):
    start = text.index(heading)
    end = text.find("\n#", start + len(heading))
    return text[start:end if end > 0 else None]


def _table(text, header_start):
    """The rows of the Markdown table whose header line starts with
    header_start, as lists of stripped cells."""
    lines = text[text.index(header_start):].splitlines()
    rows = []
    for line in lines[2:]:
        if not line.startswith("|"):
            break
        rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    assert rows, header_start
    return rows


# --- measured times: the README's set-up table, and nowhere else ------------

TIMES = dict((r[0], r[1]) for r in _table(README, "| what | time |"))


def test_the_study_time_is_timing_csv():
    """The README's time of the study from empty is results/study/timing.csv's
    wall clock, in minutes to one decimal."""
    t = pd.read_csv(RESULTS / "study/timing.csv").iloc[0]
    shown = TIMES["the 1000-run study from empty (results/study/timing.csv)"]
    assert shown == f"{t.wall_s / 60:.1f} min", (shown, t.wall_s)
    assert t.runs == _study_runs() and t.cores == 2


def test_the_set_up_table_names_its_commands():
    """The table holds one time for each of the two set-up commands, the
    study and the smoke run (so that the checks below are not vacuous)."""
    assert {"`make reproduce` (all but the accuracy study)", "`make test`", "the smoke run (above), from empty"} <= set(TIMES)
    for shown in TIMES.values():
        assert re.fullmatch(r"(\d+ min )?\d+(\.\d)? (s|min)", shown), shown


def _duration(seconds):
    """seconds as the README's set-up table states them: 6.5 s, 42 s, 15 min 32 s."""
    if seconds < 10:
        return f"{seconds:.1f} s"
    if round(seconds) < 60:
        return f"{seconds:.0f} s"
    minutes, rest = divmod(round(seconds), 60)
    return f"{minutes} min {rest} s"


def test_the_set_up_times_are_setup_csv():
    """Every other time of the README's set-up table is results/bench/setup.csv's,
    each measured from a fresh clone by benchmarks/setup_time.py (install,
    single runs, smoke run, `make test`, `make reproduce`); the measured
    `make test` passed and the measured `make reproduce` reproduced, and the
    README's example of its last line is that line."""
    t = pd.read_csv(RESULTS / "bench/setup.csv", keep_default_na=False)
    shown = {k: v for k, v in TIMES.items() if "timing.csv" not in k}
    assert set(shown) == set(t.what), (set(shown) ^ set(t.what))
    for what, seconds in zip(t.what, t.seconds):
        assert shown[what] == _duration(seconds), (what, shown[what], seconds)
    last = dict(zip(t.what, t.last_line))
    passed = r"\d+ passed(, \d+ (skipped|deselected|warnings?))* in [\d.]+s( \(\d+:\d\d:\d\d\))?"
    assert re.fullmatch(passed, last["`make test`"]), last["`make test`"]
    repro = last["`make reproduce` (all but the accuracy study)"]
    assert repro.startswith("REPRODUCED: "), repro
    example = re.search(r'"(REPRODUCED: [^"]*?), \.\.\."', _flat(README)).group(1)
    assert repro.startswith(example), (example, repro)


def test_durations_read_as_the_table_states_them():
    assert [_duration(x) for x in (6.46, 41.8, 59.6, 932.0, 2176.4)] == \
        ["6.5 s", "42 s", "1 min 0 s", "15 min 32 s", "36 min 16 s"]


_TIMED = re.compile(r"\b\d+(?:\.\d+)? ?(?:min\b|minutes\b|hours?\b)")


@pytest.mark.parametrize("page", sorted(DOCS))
def test_no_page_states_a_time_of_its_own_for_the_set_up_commands(page):
    """A time of `make test`, `make reproduce`, the smoke run or the study
    from empty is stated in the README's table alone: a sentence of a doc
    page that names one of them gives no minutes or hours (it links to the
    README instead), so that a new measurement is carried in one place."""
    for sentence in re.split(r"(?<=[.;:])\s", _flat(DOCS[page])):
        named = re.search(r"make test\b(?!-)|make reproduce|smoke (run|configuration|study)|study from empty|"
                          r"study_time\.py|timing\.csv", sentence)
        if named:
            assert not _TIMED.search(sentence), (page, sentence)


def test_the_makefile_states_no_time_of_its_own():
    """The Makefile's messages and comments point to the README for the time
    of `make reproduce` rather than state one."""
    text = (ROOT / "Makefile").read_text()
    block = text[text.index("reproduce: $(STAMP)"):text.index("report: $(STAMP)")]
    assert not _TIMED.search(block), block


# --- counts of the config --------------------------------------------------


def _study_runs():
    return STUDY["samples"] * len(STUDY["variants"]) * len(STUDY["sweep"]["levels"])


def _modelform_runs():
    m = CONFIG["modelform"]
    options = sum(len(a["options"]) for a in m["assumptions"])
    return (options + 1) * len(m["cases"]) * len(m["precompression_mpa"])


def _mentions(pattern):
    """(page, number) for every match of pattern (one group, an integer
    with or without a thousands comma) in the README and docs/."""
    return [(page, int(m.group(1).replace(",", ""))) for page, text in PAGES.items()
            for m in re.finditer(pattern, _flat(text))]


def test_the_number_of_model_form_assumptions():
    """Every '<N> (modelling) assumptions' of the docs is the config's count
    (config/config.yaml modelform.assumptions), and every '<N> options' of
    the model-form study its options."""
    m = CONFIG["modelform"]
    found = _mentions(r"\b(\d+) (?:modelling )?assumptions\b")
    assert found and all(n == len(m["assumptions"]) for _, n in found), found
    options = sum(len(a["options"]) for a in m["assumptions"])
    found = _mentions(r"\b(\d+) options\b")
    assert all(n == options for _, n in found), found


def test_the_run_counts():
    """The run counts the docs give for each target are the config's: the
    model-form study (options + 1 baseline, per case and level), the study
    (samples x variants x levels), validation (cases x levels), the hard
    cases (each, and its half-rate rerun where asked), the reduced models
    (models x cases), the further specimens; and the committed tables hold
    as many rows."""
    expected = {
        "modelform": _modelform_runs(),
        "study": _study_runs(),
        "validation": len(CONFIG["validation"]["cases"]) * len(CONFIG["validation"]["precompression_mpa"]),
        "hard cases": sum(1 + bool(c.get("half_rate")) for c in CONFIG["hard_cases"]),
        "reduced": len(CONFIG["reduced"]["models"]) * len(CONFIG["reduced"]["cases"]),
        "specimens": len(CONFIG["specimens"]),
    }
    tables = {"modelform": "modelform/summary.csv", "validation": "validation/summary.csv",
              "hard cases": "stability/hard_cases.csv", "reduced": "reduced/summary.csv",
              "specimens": "specimens/summary.csv"}
    for name, table in tables.items():
        assert len(pd.read_csv(RESULTS / table)) == expected[name], name
    rows = {r[0]: r[1] for r in _table(README, "| target | what it runs |")}
    shown = {"modelform": rows["`modelform`"], "study": rows["`study`"], "validation": rows["`validation_summary`"],
             "hard cases": rows["`stability`"], "reduced": rows["`reduced`"], "specimens": rows["`specimens`"]}
    for name, cell in shown.items():
        n = re.search(r"([\d,]+) (?:runs|simulations)", cell)
        assert n and int(n.group(1).replace(",", "")) == expected[name], (name, cell)
    # elsewhere: "<N> runs" beside the model-form study's name, the study's size
    for page, n in _mentions(r"\b(\d+) runs \(\d+ baselines"):
        assert n == expected["modelform"], page
    for page, n in _mentions(r"\b([\d,]+) (?:simulations|runs) of a (?:clay-)?brick wallette"):
        assert n == expected["study"], page


def test_the_smoke_run_as_described():
    """The smoke run's samples and levels as the README says them
    (config/smoke.yaml)."""
    smoke = yaml.safe_load((ROOT / "config/smoke.yaml").read_text())["study"]
    text = _flat(_section(README, "## First: the smoke run"))
    assert f"{smoke['samples']} samples" in text
    words = {2: "two", 3: "three"}
    assert f"{words[len(smoke['levels'])]} precompression levels" in text


# --- the numerical settings: the scene schema's defaults --------------------


def _default(*keys):
    node = SCHEMA
    for k in keys:
        node = node["properties"][k] if "properties" in node else node[k]
    return node["default"]


def test_the_precompression_tolerance():
    """Every statement of the precompression's tolerance as a default (the
    stage ends below an unbalanced-force ratio of 1e-N) is the schema's
    default, loading.precompression.ratio_tol."""
    default = float(_default("loading", "precompression", "ratio_tol"))
    pattern = (r"(?:precompression (?:is )?relaxed to an unbalanced-force ratio of|precompression to|"
               r"equilibrium \(ratio below|`ratio_tol` \()\s*(1e-\d+)")
    found = [(page, float(m.group(1))) for page, text in PAGES.items() for m in re.finditer(pattern, _flat(text))
             if not re.search(r"path|references|instead|damping 0\.8", _flat(text)[max(0, m.start() - 120):m.start()])]
    assert len(found) >= 3, found
    assert all(v == default for _, v in found), found


def test_the_loading_rate_and_damping():
    """The defaults' rate and damping as the docs state them (the scene
    schema's defaults for loading.bending.rate and numerics.damping)."""
    rate = float(_default("loading", "bending", "rate"))
    damping = float(SCHEMA["properties"]["numerics"]["properties"]["damping"]["default"])
    for page in ("docs/accuracy.md", "docs/study.md"):
        text = _flat(PAGES[page])
        assert f"damping {damping:g}" in text, page
        assert re.search(rf"{rate:.1e}".replace("e-0", "e-").replace(".", r"\.") + r" m (per|a) step", text), page


def test_the_default_cells():
    """'4x3x2 cells' as the defaults: the schema's numerics.cells default,
    and no page calls other cells the defaults."""
    cells = "x".join(str(c) for c in SCHEMA["properties"]["numerics"]["properties"]["cells"]["default"])
    for page, text in PAGES.items():
        flat = _flat(text)
        for pattern in (r"(\d+) ?x ?(\d+) ?x ?(\d+) (?:`hex8i` )?cells(?: per unit)?,? \(?(?:as )?the defaults",
                        r"[Aa]t the defaults \([^)]*?(\d+) ?x ?(\d+) ?x ?(\d+)",
                        r"defaults \(potential-crack units on (\d+)x(\d+)x(\d+)"):
            for m in re.finditer(pattern, flat):
                assert "x".join(m.groups()) == cells, (page, m.group(0))
    assert f"{cells} cells" in _flat(README)


# --- the accuracy study ----------------------------------------------------

RUNS = pd.read_csv(RESULTS / "accuracy/runs.csv")
CHOICE = pd.read_csv(RESULTS / "accuracy/choice.csv").set_index("setting")
CASES = ["joint_sv0", "joint_sv05", "brick_sv0", "brick_sv05", "mixed_sv05"]


def _setting(model, cells, refined):
    """The accuracy study's setting of a row of docs/accuracy.md's table:
    'the defaults' is 'default'; else the unit model, cells and refinement
    make its name (potential-crack 4x3x2 head joints: pc_c4x3x2_head; no:
    _r1; all joints: _r121; "damping 0.8, half the rate": _d08_half; "at 1.5
    times the rate": _rate15; elasto-plastic 9x4x3: ep_c9x4x3)."""
    if "**the defaults**" in model:
        return "default"
    if model.startswith("elasto-plastic"):
        return f"ep_c{cells}"
    suffix = {"head joints": "head", "no": "r1", "all joints": "r121"}[refined]
    if "damping 0.8" in model and "half the rate" in model:
        suffix += "_d08_half"
    if "1.5 times the rate" in model:
        suffix += "_rate15"
    return f"pc_c{cells}_{suffix}"


def _run_time(t):
    return f"{t:.1f} s" if t < 10 else f"{t:.0f} s"


def test_the_accuracy_table_is_the_committed_study():
    """docs/accuracy.md's table states what results/accuracy/runs.csv holds:
    per row each case's error of P_max (in %, with its sign, the two levels
    of a mode side by side), a mode other than the reference's marked, and
    the mean run time over the five cases (a decimal below 10 s)."""
    rows = _table(DOCS["docs/accuracy.md"], "| unit model | cells per unit |")
    assert len(rows) >= 12
    for model, cells, refined, joint, brick, mixed, time in rows:
        g = RUNS[RUNS.setting == _setting(model, cells, refined)].set_index("case")
        assert len(g) == 5, model
        shown = [x.strip("* ") for x in (joint + " / " + brick + " / " + mixed).replace("%", "").split("/")]
        for case, cell in zip(CASES, shown):
            value = cell.split("(")[0].strip().strip("*")
            assert value == f"{100 * g.error[case]:+.1f}", (model, cells, case, value, g.error[case])
            assert ("(" in cell) == (not g.mode_ok[case]), (model, cells, case)
        assert time == _run_time(g.wall_time_s.mean()), (model, cells, time)


def test_the_defaults_accuracy_as_quoted():
    """The largest error of the defaults and of the elasto-plastic model on
    15x7x5 cells, and its cost against the defaults', as the README's three
    lines and docs/accuracy.md quote them (results/accuracy/choice.csv)."""
    d, ep = CHOICE.loc["default"], CHOICE.loc["ep_c15x7x5"]
    assert d.ok and d.modes_ok and d.default
    readme = _flat(_section(README, "## Accuracy"))
    assert f"within {100 * d.max_abs_error:.1f} %" in readme
    assert f"15x7x5 cells for {100 * ep.max_abs_error:.1f} %" in readme
    ratio = f"{ep.total_time_s / d.total_time_s:.0f} times the"
    assert ratio in readme
    acc = _flat(DOCS["docs/accuracy.md"])
    assert f"largest error {100 * d.max_abs_error:.2f} %" in acc
    assert ratio in acc
    knee = CHOICE[CHOICE.knee].iloc[0]
    steps = RUNS[RUNS.setting == knee.name].steps.sum()
    assert f"{100 * knee.max_abs_error:.2f} % at most, {steps:,} steps" in acc
    assert f"in {RUNS[RUNS.setting == 'default'].steps.sum():,} steps" in acc
    # the elasto-plastic model's error, its case's mode and its cost, as accuracy.md gives them
    ep_runs = RUNS[RUNS.setting == "ep_c15x7x5"].set_index("case")
    mode = ep_runs.error.abs().idxmax().split("_")[0]
    assert f"2 % ({100 * ep.max_abs_error:.1f} %, {mode} failure), {ratio} defaults' cost" in acc
    assert (f"five cases take {ep.total_time_s:.1f} s against the defaults' {d.total_time_s:.1f} s "
            "(results/accuracy/choice.csv, `total_time_s`)") in acc
    # no other cost ratio of the two on the page
    for m in re.finditer(r"(\d+) times the defaults' (?:cost|time)", acc):
        assert m.group(0).startswith(ratio.removesuffix(" the")), m.group(0)


def test_the_subsample_table():
    """docs/accuracy.md's subsample table and its summary sentence are
    results/accuracy/subsample.csv's."""
    sub = pd.read_csv(RESULTS / "accuracy/subsample.csv")
    rows = _table(DOCS["docs/accuracy.md"], "| sigma_v | mean P_max defaults / elasto-plastic |")
    assert len(rows) == len(sub)
    for (level, means, cov, brick, same, ratio), s in zip(rows, sub.itertuples()):
        assert means == f"{s.mean_kN_default:.2f} / {s.mean_kN_fine:.2f} kN ({100 * s.mean_diff:+.1f} %)", means
        assert cov == f"{s.cov_default:.3f} / {s.cov_fine:.3f}"
        assert brick.split(" of")[0] == f"{s.brick_default} / {s.brick_fine}"
        assert same == f"{s.same_mode} of {s.runs}"
        assert ratio == f"mean {s.ratio_mean:.3f}, COV {s.ratio_cov:.3f}"
    acc = _flat(DOCS["docs/accuracy.md"])
    assert f"same failure mode in {sub.same_mode.sum()} of {sub.runs.sum()} runs" in acc
    assert f"means within {100 * sub.mean_diff.abs().max():.2f} %" in acc


def test_the_references_cost():
    """The hours the 45 reference runs take, as the README and
    docs/accuracy.md give them (results/accuracy/references.csv: the sum of
    the runs' times on two cores)."""
    ref = pd.read_csv(RESULTS / "accuracy/references.csv")
    hours = f"{ref.wall_time_s.sum() / 2 / 3600:.1f} hours"
    assert f"its {len(ref)} reference runs alone take {hours}" in _flat(README)
    assert f"take {hours} of two cores (the sum of the {len(ref)} runs' times" in _flat(DOCS["docs/accuracy.md"])


# --- the study against the source paper ------------------------------------

PAPER = pd.read_csv(RESULTS / "study/paper_comparison.csv")


def test_the_headline():
    """The README's headline: the all-data means' offset from the paper's
    (smallest to largest), the published COVs inside our intervals, the
    increase of the mean from the lowest to the highest level."""
    means = PAPER[(PAPER["mode"] == "all") & (PAPER["item"] == "F_max mean (kN)")]
    offset = f"+{means.difference_pct.min():.1f} to +{means.difference_pct.max():.1f} %"
    for page, text in PAGES.items():
        for m in re.finditer(r"\+\d+\.\d to \+\d+\.\d % above the paper's", _flat(text)):
            assert m.group(0) == offset + " above the paper's", (page, m.group(0))
    assert offset in _flat(README)
    covs = PAPER[PAPER["item"] == "F_max COV"]
    assert f"({covs.paper_inside.sum()} of its {len(covs)} COVs)" in _flat(README)
    rise = PAPER[(PAPER["item"].str.startswith("increase")) & (PAPER["mode"] == "all")].ours.iloc[0]
    assert f"rises by {rise:.0f} %" in _flat(README)


# --- names of the code the docs cite ----------------------------------------

SRC = ROOT / "src" / "masonrydem"
MODULES = {p.relative_to(SRC).with_suffix("").as_posix().replace("/", ".").removesuffix(".__init__"): p
           for p in SRC.rglob("*.py")}


def _defines(path, name):
    return re.search(rf"^\s*(?:def|class) {re.escape(name)}\b|^\s*{re.escape(name)}\s*[:=]",
                     path.read_text(), re.M)


def _resolve(dotted):
    """The module file and the names left for a dotted reference to the
    package's code (`equations._lasso`, `masonrydem.analysis.predict.predict`,
    `kernels.step.specialised`), or None when its head names no module."""
    parts = dotted.removeprefix("masonrydem.").split(".")
    for k in range(len(parts), 0, -1):
        head = ".".join(parts[:k])
        hits = [m for m in MODULES if m == head or m.endswith("." + head)]
        if hits:
            return MODULES[sorted(hits, key=len)[0]], parts[k:]
    return None


def _config_keys(node, prefix=""):
    """The dotted keys of the workflow's config (`study.curve_points`): a
    setting, not code, where its head is also a package's name."""
    keys = set()
    for k, v in (node.items() if isinstance(node, dict) else ()):
        keys |= {prefix + k} | _config_keys(v, prefix + k + ".")
    return keys


def test_the_code_the_docs_cite_exists():
    """Every `module.name` (or `package.module.name`) of the package that the
    README and docs/ cite names a function, class or constant its module
    defines (a method: `Block.interpolate_points`, its class's); a dotted
    key of the workflow's config is a setting, not code."""
    settings = _config_keys(CONFIG)
    missing, checked = [], 0
    for page, text in PAGES.items():
        for ref in set(re.findall(r"`((?:masonrydem\.)?[a-z_][a-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)+)`", text)):
            found = _resolve(ref)
            if ref.rsplit(".", 1)[1] in ("py", "yaml", "md", "csv", "json", "parquet", "png") or found is None \
                    or not found[1] or ref in settings:
                continue
            path, names = found
            checked += 1
            if not all(_defines(path, n) for n in names[:2]):
                missing.append((page, ref))
    assert checked >= 20 and not missing, missing


def test_what_a_run_costs():
    """docs/speed.md's mean steps of a study run, its batches and the core
    time a run costs are results/study/timing.csv's."""
    t = pd.read_csv(RESULTS / "study/timing.csv").iloc[0]
    text = _flat(_section(DOCS["docs/speed.md"], "## What a run costs"))
    assert f"averages {t.mean_steps:,.0f} steps" in text
    assert f"batches of {t.batch_runs} runs on {t.lanes} lanes" in text
    assert f"a run costs {t.core_s_per_run:.3f} s of one core" in text


def _width(cpu):
    """The vector width a benchmark file's cpu names, as speed.md says it."""
    return re.search(r"\((AVX-512|AVX2|no AVX2)\)", cpu).group(1)


def test_where_a_run_s_time_goes():
    """docs/speed.md's table of a run's cost is results/bench/run_cost.csv
    (benchmarks/run_cost.py): a row per part, alone and in a batch of the
    workflow's lanes, to the millisecond; the mean steps; the machine."""
    t = pd.read_csv(RESULTS / "bench/run_cost.csv").set_index("part")
    batch = f"batch of {t.lanes.iloc[0]}"
    assert t.lanes.iloc[0] == CONFIG["batch"]["lanes"] and t.runs.iloc[0] == 32
    text = DOCS["docs/speed.md"]
    rows = _table(text, f"| part | alone | a {batch} |")
    parts = [row[0].strip("*").split()[0] for row in rows]
    assert [("total" if p == "a" else p) for p in parts] == ["build", "load", "steps", "stages", "written", "total"]
    for part, row in zip(t.index, rows):
        assert [c.strip("*") for c in row[1:]] == [f"{t.loc[part, w]:.3f}" for w in ("alone", batch)], row
    assert f"{t.loc['mean_steps', 'alone']:,.0f} steps a run" in rows[2][0]
    section = _flat(_section(text, "## What a run costs"))
    assert f"a 2-core x86-64 with {_width(t.cpu.iloc[0])}" in section and t.cores.iloc[0] == 2


SCALE_PARTS = [("planning_s", "the start and the plan (s)"), ("batches_s", "the batches (s)"),
               ("collect_s", "collect (s)"), ("analysis_s", "the analysis (s)"),
               ("tail_s", "after the last job (s)"), ("report_s", "the report (s)")]


def test_the_study_at_scale():
    """docs/speed.md's table of the study at 1,000 and 10,000 runs is
    results/bench/study_scale.csv (benchmarks/study_scale.py): each part's
    seconds, the core-seconds a run, the peak memory; the ratios said of
    it; and the Sobol table is study_scale_sobol.csv's."""
    t = pd.read_csv(RESULTS / "bench/study_scale.csv").set_index("runs")
    assert list(t.index) == [1000, 10000] and (t.cores_used == 2).all()
    text = DOCS["docs/speed.md"]
    rows = _table(text, "| part | 1,000 runs | 10,000 runs |")
    assert [r[0].strip("*") for r in rows] == [name for _, name in SCALE_PARTS] + [
        "all, core-seconds a run", "peak memory of a process (MB)"]
    for (col, _), row in zip(SCALE_PARTS, rows):
        assert row[1:] == [f"{t.loc[n, col]:.1f}" for n in t.index], row
    assert [c.strip("*") for c in rows[-2][1:]] == [f"{t.loc[n, 'core_s_per_run']:.3f}" for n in t.index]
    assert rows[-1][1:] == [f"{t.loc[n, 'peak_rss_mb']:.0f}" for n in t.index]
    section = _flat(_section(text, "## The study at scale"))
    assert f"a 2-core x86-64 with {_width(t.cpu.iloc[0])}" in section
    ratio = t.loc[10000, "core_s_per_run"] / t.loc[1000, "core_s_per_run"]
    assert f"{ratio:.2f} times the cost per run at 1,000" in section
    for col in ("batches_s", "analysis_s"):
        assert f"{t.loc[10000, col] / t.loc[1000, col]:.1f} times" in section, col
    grows = {col: t.loc[10000, col] / t.loc[1000, col] for col, _ in SCALE_PARTS if col != "batches_s"}
    assert "every other part less than five times as long" in section and max(grows.values()) < 5, grows
    assert ("No part grows faster than the runs" in section
            and max(t.loc[10000, col] / t.loc[1000, col] for col, _ in SCALE_PARTS) <= 10)
    sobol = pd.read_csv(RESULTS / "bench/study_scale_sobol.csv")
    rows = _table(text, "| σ<sub>v</sub> (MPa) | input |")
    for row in rows:
        for cell, n in zip(row[2:], (100, 1000)):
            g = sobol[(sobol.samples == n) & (sobol.sigma_v_mpa == float(row[0])) & (sobol["input"] == row[1])]
            x = g.iloc[0]
            assert cell == f"{x.ST:.2f} ({x.ST_lo:.2f} to {x.ST_hi:.2f})", (row, cell)
    assert len(rows) == 2 * sobol.sigma_v_mpa.nunique()
    width = sobol.assign(w=sobol.ST_hi - sobol.ST_lo).pivot_table("w", ["sigma_v_mpa", "input"], "samples")
    narrower = width[100] / width[1000]
    assert (f"{narrower.min():.1f} to {narrower.max():.1f} times narrower ({narrower.median():.1f} the median over "
            f"the four inputs and five levels)") in section


def test_the_lanes_table():
    """docs/speed.md's table of the lanes and the ratios said of it are
    results/bench/bench.json's potential-crack model (benchmarks/bench.py)."""
    bench = json.loads((RESULTS / "bench/bench.json").read_text())
    model = bench["models"]["potential-crack"]
    lanes = model["lanes"]
    text = DOCS["docs/speed.md"]
    rows = _table(text, "| lanes S |")
    assert [r[0] for r in rows] == list(lanes)
    for row in rows:
        x = lanes[row[0]]
        assert row[1:] == [f"{x['step_us']:.1f}", f"{x['ns_per_cell_step']:.1f}", f"{x['ns_per_subcontact_step']:.1f}"]
    one, eight = lanes["1"], lanes["8"]
    flat = _flat(text)
    assert f"A batch of 8 costs {eight['step_us'] / one['step_us']:.2f} times a batch of one" in flat
    assert f"a cell costs {eight['ns_per_cell_step']:.0f} ns a sample against {one['ns_per_cell_step']:.0f} alone" in flat
    assert eight["ns_per_subcontact_step"] < one["ns_per_subcontact_step"] / 2      # "less than half"
    assert lanes["32"]["step_us"] > eight["step_us"]                                # 32 lanes slower per sample
    assert f"{model['cells']} cells and {model['subcontacts']:,} joint sub-contacts" in flat
    assert f"A lane-step costs {eight['step_us']:.1f} us at 8 lanes" in flat
    assert f"at 1 us a lane-step, would run the study's steps about {eight['step_us']:.0f} times faster" in flat


def test_the_bootstrap_s_time():
    """docs/study.md's seconds of one core for the equations' bootstrap are
    results/bench/bench.json's time per resample times the study's
    resamples (config/config.yaml)."""
    boot = json.loads((RESULTS / "bench/bench.json").read_text())["bootstrap"]
    seconds = boot["jobs1_ms_per_resample"] * CONFIG["study"]["bootstrap"]["resamples"] / 1e3
    assert f"This takes about {seconds:.0f} s of one core (`make bench`" in _flat(DOCS["docs/study.md"])


def test_the_reduced_models_table():
    """docs/findings.md's reduced-models table is results/reduced/summary.csv:
    the elasto-plastic model's P_max and time, each other model's change of
    P_max, its failure mode where it differs, and its speed-up."""
    red = pd.read_csv(RESULTS / "reduced/summary.csv")
    rows = _table(DOCS["docs/findings.md"], "| case | elasto-plastic 9x4x3 |")
    assert len(rows) == red.case.nunique()
    for row, (case, g) in zip(rows, red.groupby("case", sort=False)):
        g = g.set_index("model")
        full = g.loc["full"]
        assert row[1].startswith(f"{full.P_max_kN:.3f} kN") and row[1].endswith(f"{full.wall_time_s:.1f} s"), row
        for cell, model in zip(row[2:], ("pc", "elastic", "rigid")):
            x = g.loc[model]
            assert cell.startswith(f"{x.change_pct:+.1f} %"), (case, model, cell)
            speed = f"{x.speedup:.1f} x faster" if x.speedup < 10 else f"{x.speedup:.0f} x faster"
            assert cell.endswith(speed), (case, model, cell, x.speedup)
            assert (f"({x.failure_mode})" in cell) == (x.failure_mode != "joint" or full.failure_mode != "joint")


def test_the_seeded_faults():
    """The README's count of `make mutants`' seeded faults is the length of
    benchmarks/mutants.py's FAULTS list (its entries counted in the source:
    each starts a tuple line of its own)."""
    source = (ROOT / "benchmarks/mutants.py").read_text()
    body = source[source.index("FAULTS = ["):]
    body = body[:body.index("\n]\n")]
    import ast
    faults = ast.literal_eval(body[len("FAULTS = "):] + "]")
    assert f"seeds {len(faults)} faults" in _flat(README)


def test_the_batch_size_as_the_config_gives_it():
    """docs/workflow.md and docs/cluster.md give the study's batch size
    (config batch.runs) as config/config.yaml sets it, and the columns of
    results/study/timing.csv that workflow.md names exist."""
    runs = CONFIG["batch"]["runs"]
    assert f"`batch.runs` samples ({runs})" in _flat(DOCS["docs/workflow.md"])
    assert f"(config `batch.runs`, {runs})" in DOCS["docs/cluster.md"]
    timing = pd.read_csv(RESULTS / "study/timing.csv")
    named = set(re.findall(r"\(`([a-z_]+)`", _flat(_section(DOCS["docs/workflow.md"], "`benchmarks/study_time.py`"))))
    assert named and named <= set(timing.columns), named - set(timing.columns)


def test_the_finest_path_level_s_run_time():
    """The minutes a run of the paths' finest level (21x10x8) takes, as
    docs/accuracy.md and docs/known-problems.md give them, are
    results/accuracy/references.csv's shortest and longest; the level beyond
    it has about half a million tetrahedra."""
    ref = pd.read_csv(RESULTS / "accuracy/references.csv")
    finest = ref[ref.cells == "21x10x8"].wall_time_s / 60
    assert len(finest) == ref.case.nunique()
    span = f"{finest.min():.0f} to {finest.max():.0f} minutes"
    assert f"a 21x10x8 run {span}" in _flat(DOCS["docs/accuracy.md"])
    known = _flat(DOCS["docs/known-problems.md"])
    assert f"the 21x10x8 level's {span} a run" in known
    tets_per_cell = ref.tets.iloc[0] / (24 * math.prod(int(x) for x in ref.cells.iloc[0].split("x")))
    assert "(23x11x9, about half a million tetrahedra)" in known
    assert 0.4e6 < 24 * 23 * 11 * 9 * tets_per_cell < 0.6e6


def test_the_accuracy_studys_costs_as_its_tables_give_them():
    """docs/accuracy.md's costs from the accuracy study's tables: the runs
    that moving the defaults reruns (results/accuracy/runs.csv: all but the
    path's, those whose setting is a path's included, and their minutes of
    two cores), and the growth with the wallette's size (scaling.csv: the
    seconds a run at 24, 48 and 96 units, 6, 12 and 24 courses, and the
    exponents in units and in cells along the unit)."""
    acc = _flat(DOCS["docs/accuracy.md"])
    runs = pd.read_csv(RESULTS / "accuracy/runs.csv")
    other = runs[(runs.kind != "path") & ~runs.setting.str.startswith("path")]
    assert (f"reruns the other {len(other)} runs ({other.wall_time_s.sum() / 2 / 60:.1f} minutes of two cores"
            in acc)
    scaling = pd.read_csv(RESULTS / "accuracy/scaling.csv")
    units, cells = (scaling[scaling.against == a] for a in ("units", "cells"))
    assert units["size"].tolist() == [24, 48, 96]

    def exponent(t):        # the power law's, fitted here in log-log
        return np.polyfit(np.log(t["size"]), np.log(t.run_time_s), 1)[0]
    assert (f"(6, 12, 24 courses: {', '.join(f'{t:.1f}' for t in units.run_time_s)} s a run at the defaults, "
            f"exponent {exponent(units):.2f};" in acc)
    assert f"as (cells along the unit)^{exponent(cells):.1f}." in acc


def test_the_crack_penalty_as_the_runs_give_it():
    """docs/accuracy.md's changes of P_max with the crack interfaces'
    penalty at 300 and 1000 E/L, against the defaults' runs of the same
    case (results/accuracy/runs.csv): brick failure at 0 MPa, mixed at
    0.5 MPa, joint at 0 MPa."""
    runs = pd.read_csv(RESULTS / "accuracy/runs.csv")
    p = {(r.case, r.setting): r.P_max_kN for r in runs.itertuples()}

    def change(case):
        return " and ".join(f"{100 * (p[(case, f'crack_kn_ratio_{k:.1f}')] / p[(case, 'default')] - 1):+.1f}"
                            for k in (300, 1000))
    acc = _flat(DOCS["docs/accuracy.md"])
    assert (f"{change('brick_sv0')} % in brick failure, {change('mixed_sv05')} % in mixed failure, "
            f"{change('joint_sv0')} % at 0 MPa in joint failure" in acc)


def test_the_vertical_defaults_as_quoted():
    """docs/accuracy.md's vertical-bending table is
    results/accuracy/vertical.csv's largest error per candidate, the
    references' distance from the finer ones as quoted, and the vertical
    defaults it names are the schema's default_vertical."""
    runs = pd.read_csv(RESULTS / "accuracy/vertical.csv")
    worst = runs.groupby("candidate").error.agg(lambda e: e.abs().max())
    names = {"the horizontal defaults": "horizontal defaults", "bed joints refined, the horizontal rate":
             "bed refined, horizontal rate", "**the vertical defaults**": "vertical defaults",
             "bed joints refined, 1e-8 m per step": "bed refined, 1e-8"}
    rows = _table(DOCS["docs/accuracy.md"], "| settings | largest error |")
    assert [r[0] for r in rows] == list(names)
    for shown, error in rows:
        assert error == f"{100 * worst[names[shown]]:.2f} %", shown
    acc = _flat(_section(DOCS["docs/accuracy.md"], "## Vertical bending"))
    assert f"within {100 * worst['finer reference']:.2f} % of finer ones" in acc
    vertical = runs[runs.candidate == "vertical defaults"].iloc[0]
    bending = SCHEMA["properties"]["loading"]["properties"]["bending"]["properties"]
    refine = SCHEMA["properties"]["numerics"]["properties"]["subcontact_refine"]["default_vertical"]
    assert vertical.rate == bending["rate"]["default_vertical"] and f"{vertical.rate:.1e}".replace("e-0", "e-") in acc
    assert vertical.bed_refine == "x".join(map(str, refine["bed"]))


def test_both_directions_as_quoted():
    """docs/lab-to-design.md's table of both directions is
    results/studies/waal_lab/vertical/study/directions.csv's, and its
    wallette tests' percentiles and p-value are wallette_tests.csv's and
    the agreement test's on it."""
    from masonrydem.analysis.directions import agreement
    folder = RESULTS / "studies/waal_lab/vertical/study"
    table = pd.read_csv(folder / "directions.csv")
    rows = _table(DOCS["docs/lab-to-design.md"], "| p (MPa) | f_x1 (95 %) |")
    assert len(rows) == len(table)
    for (p, f1, f2, mu, k1, k2), r in zip(rows, table.itertuples()):
        assert p == f"{r.p_mpa:g}"
        assert f1 == f"{r.f_x1_mpa:.3f} ({r.f_x1_low:.3f} to {r.f_x1_high:.3f})"
        assert f2 == f"{r.f_x2_mpa:.3f} ({r.f_x2_low:.3f} to {r.f_x2_high:.3f})"
        assert mu == f"{r.mu:.3f} ({r.mu_low:.3f} to {r.mu_high:.3f})"
        assert k1 == f"{r.f_x1_k_mpa:.3f} / {r.en_fxk1_app_mpa:.2f}" and k2 == f"{r.f_x2_k_mpa:.3f} / {r.en_fxk2_mpa:.2f}"
    text = _flat(_section(DOCS["docs/lab-to-design.md"], "## 11."))
    assert f"correlation ({table.pair_correlation.iloc[0]:.2f} at 0 MPa" in text
    tests = pd.read_csv(folder / "wallette_tests.csv")
    for direction, g in tests.groupby("direction"):
        lo, hi = 100 * g.percentile.min(), 100 * g.percentile.max()
        assert f"at the {lo:.0f}th to {hi:.0f}rd" in text or f"at the {lo:.0f}th to {hi:.0f}th" in text, direction
    assert f"p = {agreement(tests, 'p_mpa')[2]:.3f}" in text


def test_the_fracture_energys_effect_as_quoted():
    """docs/formulation.md's peaks of the committed vertical scene over its
    brittle limit f_tj Z (M = P a / 2, Z of the section as modelled), at
    the vertical defaults without precompression, are
    results/accuracy/vertical.csv's."""
    from masonrydem.scene import build_scene
    scene = build_scene(str(ROOT / "config/scenes/solid_vertical.yaml"))
    g, a = scene.geometry, scene.loading.bending.shear_span
    x0, x1 = g.common_span
    Z = (x1 - x0) * g.unit_width ** 2 / 6
    runs = pd.read_csv(RESULTS / "accuracy/vertical.csv")
    runs = runs[(runs.candidate == "vertical defaults") & (runs.pressure_mpa == 0)].sort_values("f_tj_mpa")
    ratios = [r.P_max_kN * 1e3 * a / 2 / (r.f_tj_mpa * 1e6 * Z) for r in runs.itertuples()]
    text = _flat(DOCS["docs/formulation.md"])
    assert (f"{ratios[0]:.2f}, {ratios[1]:.2f} and {ratios[2]:.2f} times f_tj Z at f_tj = "
            + ", ".join(f"{f:g}" for f in runs.f_tj_mpa[:2]) + f" and {runs.f_tj_mpa.iloc[2]:g} MPa") in text


# --- the geometry study (docs/geometry-study.md) ----------------------------

GEOMETRY = yaml.safe_load((ROOT / "config/studies/geometry.yaml").read_text())
GEO_PAGE = _flat(DOCS["docs/geometry-study.md"])
FORMATS = sorted((ROOT / "config/studies/formats").glob("[a-z][a-z].yaml"))


def _levels_mpa(study):
    return [float(x.split()[0]) for x in study["sweep"]["levels"]]


def test_the_geometry_studys_draws_as_its_study_file_gives_them():
    """docs/geometry-study.md's samples, levels, the four dimensions'
    ranges (its table and the box `predict` holds to) and the run counts
    are config/studies/geometry.yaml's and config/studies/formats/*.yaml's."""
    levels = _levels_mpa(GEOMETRY)
    assert levels == [0, 0.15, 0.5]
    assert f"{GEOMETRY['samples']} samples at 0, 0.15 and 0.5 MPa" in GEO_PAGE
    ranges = {}
    for name, words in (("L", "L, brick length"), ("H", "H, brick height"), ("W", "W, brick width (the wall's thickness)"),
                        ("t", "t, joint thickness")):
        var = GEOMETRY["variables"][name]
        lo, hi = (float(b.split()[0]) for b in var["bounds"])
        assert var["bounds"][0].endswith("mm") and var["distribution"] == "uniform"
        assert f"| {words} | {var['setting']} | uniform {lo:g} to {hi:g} mm |" in DOCS["docs/geometry-study.md"], name
        ranges[name] = f"{lo:g} to {hi:g} mm"
    assert (f"L {ranges['L']}, H {ranges['H']}, W {ranges['W']}, joints {ranges['t']}" in GEO_PAGE)
    formats = [yaml.safe_load(p.read_text()) for p in FORMATS]
    assert len(formats) == 4 and len({f["samples"] * len(f["sweep"]["levels"]) for f in formats}) == 1
    each = formats[0]["samples"] * len(formats[0]["sweep"]["levels"])
    assert (f"The geometry study has {GEOMETRY['samples'] * len(levels)} runs and each format {each}."
            in GEO_PAGE)
    assert f"and {formats[0]['samples']} samples of the four material variables at the same three levels" in GEO_PAGE


def test_the_geometry_studys_statistics_and_equations():
    """The geometry study's runs, the ones left out, its means, COVs and
    brick shares per level (statistics.csv) and its equations with their
    runs and errors (equations.csv), as docs/geometry-study.md states them."""
    folder = RESULTS / "studies/geometry/study"
    stats = pd.read_csv(folder / "statistics.csv")
    every = stats[stats["mode"] == "all"]
    runs, kept = int((every["count"] + every.excluded).sum()), int(every["count"].sum())
    left_out = every[every.excluded > 0]
    words = {1: "one", 2: "two", 3: "three"}
    assert len(left_out) == 1
    assert (f"The geometry study's {runs} runs give {kept} strengths: {words[int(left_out.excluded.iloc[0])]} at "
            f"{left_out.sigma_v_mpa.iloc[0]:g} MPa stop") in GEO_PAGE
    for r in every.itertuples():
        assert (f"{r.sigma_v_mpa:g} MPa: mean {r.P_max_mean_kN:.2f} kN, COV {r.P_max_cov:.2f}, brick failures "
                f"{100 * r.brick_share:.0f} %") in GEO_PAGE, r.sigma_v_mpa
    eqs = pd.read_csv(folder / "equations.csv").set_index("mode")
    for mode in ("joint", "brick"):
        e = eqs.loc[mode]
        assert (f"- {mode} failure ({e.n} runs): {e.equation}; MAPE {e.mape_pct:.1f} % in sample, "
                f"{e.cv_mape_pct:.1f} % out of fold") in DOCS["docs/geometry-study.md"], mode
    low = eqs.loc["lower of two"]
    assert low.n == kept
    assert (f"the lower of the two ({low.n} runs): MAPE {low.mape_pct:.1f} %, failure mode right in "
            f"{100 * low.mode_agreement:.0f} % of the runs") in GEO_PAGE


def test_the_held_out_formats_as_quoted():
    """docs/geometry-study.md's table of the formats is
    results/studies/geometry_formats.csv row by row (the brick and joint,
    runs, MAPE, bias, modes right, the fixed-geometry equations' scores),
    and the sentences after it its range of the held-out errors, its
    largest bias and the Willis brick's cost of the proportions."""
    t = pd.read_csv(RESULTS / "studies/geometry_formats.csv")
    rows = _table(DOCS["docs/geometry-study.md"], "| format | brick L x W x H, joint (mm) |")
    assert [r[0] for r in rows] == list(t.format)
    for row, r in zip(rows, t.itertuples()):
        brick = "" if pd.isna(r.L_mm) else f"{r.L_mm:g} x {r.W_mm:g} x {r.H_mm:g}, {r.t_mm:g}"
        own = "" if pd.isna(r.own_mape_pct) else f"MAPE {r.own_mape_pct:.1f} %, bias {r.own_bias_pct:+.1f} %"
        assert row[1:] == [brick, f"{r.runs}", f"{r.mape_pct:.1f} %", f"{r.bias_pct:+.1f} %",
                           f"{100 * r.mode_agreement:.0f} %", own], row
    fitted = t[t.format.str.startswith("fitted")].iloc[0]
    held = t[~t.format.str.startswith("fitted")]
    count = {4: "four", 5: "five", 6: "six", 7: "seven"}[len(held)]
    assert (f"On the {count} formats it was not fitted to, the lower of the two equations makes "
            f"{held.mape_pct.min():.1f} to {held.mape_pct.max():.1f} %, against {fitted.mape_pct:.1f} % in sample"
            in GEO_PAGE)
    worst = held.loc[held.bias_pct.abs().idxmax()]
    assert f"The largest bias, {worst.bias_pct:+.1f} % ({worst.format})" in GEO_PAGE
    willis = t[t.format == "Willis"].iloc[0]
    assert (f"they score {willis.mape_pct:.1f} %, against {willis.own_mape_pct:.1f} % for the fixed-geometry "
            in GEO_PAGE)
    assert (f"cost {willis.mape_pct - willis.own_mape_pct:.1f} points ({willis.mape_pct:.2f} against "
            f"{willis.own_mape_pct:.2f} %)" in GEO_PAGE)
    eqs = pd.read_csv(RESULTS / "studies/geometry/study/equations.csv").set_index("mode")
    assert fitted.runs == eqs.loc["lower of two"].n


# --- the worked examples: docs/lab-to-design.md, docs/your-own-study.md -----

NUMBER = r"(\d+(?:\.\d+)?)"
WORDS = {2: "two", 3: "three", 4: "four", 5: "five", 6: "six", 7: "seven", 8: "eight", 9: "nine", 10: "ten",
         12: "twelve", 20: "twenty"}


def _agrees(shown, value, digits=4):
    """Whether the number shown is a rounding, at its own decimals, of a
    value that a CSV cell written to `digits` significant digits allows."""
    decimals = len(shown.split(".")[1]) if "." in shown else 0
    cell = 0.5 * 10 ** (math.floor(math.log10(abs(value))) - digits + 1) if value else 0.0
    return abs(float(shown) - value) <= cell + 0.5 * 10 ** -decimals + 1e-12


def _numbers_as(text, pattern, expected):
    """The numbers of pattern's groups in text, each a rounding of its
    expected value (see _agrees)."""
    m = re.search(pattern, text)
    assert m, pattern
    shown = m.groups()
    assert len(shown) == len(expected)
    for s, v in zip(shown, expected):
        assert _agrees(s, v), (m.group(0), s, v)


def test_the_design_example_as_quoted():
    """docs/lab-to-design.md's worked example: the study's size
    (config/studies/waal_lab.yaml), the design table's caption as the
    report prints it (results/studies/waal_lab/report/design.rst) and the
    paragraph that reads it, from results/studies/waal_lab/design/design.csv
    and the study's brick shares (statistics.csv)."""
    page = DOCS["docs/lab-to-design.md"]
    flat = _flat(page)
    study = yaml.safe_load((ROOT / "config/studies/waal_lab.yaml").read_text())
    levels = _levels_mpa(study)
    runs = study["samples"] * len(levels)
    assert f"{study['samples']} samples at {levels[0]:g} and {levels[1]:g} MPa, {runs} runs" in flat
    assert f"runs the {runs} simulations and the design rule" in flat
    caption = (RESULTS / "studies/waal_lab/report/design.rst").read_text()
    block = page[page.index("The design table's report caption says:"):]
    block = block[block.index("```\n") + 4:]
    lines = block[:block.index("```")].splitlines()
    assert len(lines) == len(levels)
    for line in lines:
        assert f"- {line}\n" in caption, line
    d = pd.read_csv(RESULTS / "studies/waal_lab/design/design.csv")
    r0, r1 = d.iloc[0], d.iloc[1]
    _numbers_as(flat, rf"characteristic flexural strength is {NUMBER} MPa without precompression \(95 %: {NUMBER} to "
                      rf"{NUMBER} MPa\) and {NUMBER} MPa at {NUMBER} MPa \({NUMBER} to {NUMBER} MPa\); with gamma_M = "
                      rf"{NUMBER} its design values are {NUMBER} and {NUMBER} MPa, against EN 1996-1-1's f_xd2 = "
                      rf"{NUMBER} / {NUMBER} = {NUMBER} MPa at both",
                [r0.f_xk_mpa, r0.f_xk_lo_mpa, r0.f_xk_hi_mpa, r1.f_xk_mpa, r1.p_mpa, r1.f_xk_lo_mpa, r1.f_xk_hi_mpa,
                 r0.gamma_M, r0.f_xd_mpa, r1.f_xd_mpa, r0.f_xk2_mpa, r0.gamma_M, r0.f_xd2_mpa])
    assert r0.p_mpa == 0 and (d.f_xd2_mpa == r0.f_xd2_mpa).all()
    n = {name: v["provenance"]["n"] for name, v in study["variables"].items() if "provenance" in v}
    m = re.search(rf"lab's (\w+) bond-wrench tests \({NUMBER} to {NUMBER} MPa\) weigh more than the study's (\d+) runs "
                  rf"\({NUMBER} to {NUMBER}\); at {NUMBER} MPa, where most runs break through the units, the lab's "
                  rf"(\w+) unit tests \({NUMBER} to {NUMBER}\) still weigh more than the runs \({NUMBER} to {NUMBER}\)",
                  flat)
    assert m and m.group(1) == WORDS[n["bond"]] and m.group(8) == WORDS[n["mor"]], m
    assert int(m.group(4)) == r0.runs == study["samples"]
    shown = [g for k, g in enumerate(m.groups(), 1) if k not in (1, 4, 8)]
    for s, v in zip(shown, [r0.lab_only_lo_mpa, r0.lab_only_hi_mpa, r0.runs_only_lo_mpa, r0.runs_only_hi_mpa,
                            r1.p_mpa, r1.lab_only_lo_mpa, r1.lab_only_hi_mpa, r1.runs_only_lo_mpa,
                            r1.runs_only_hi_mpa]):
        assert _agrees(s, v), (s, v)
    # "where the joints govern" at 0 MPa, "where most runs break through the units" at the other level
    share = pd.read_csv(RESULTS / "studies/waal_lab/study/statistics.csv").query("mode == 'all'").set_index("p_mpa")
    assert share.brick_share[0] < 0.5 < share.brick_share[r1.p_mpa]
    _numbers_as(flat, rf"The effective sample size is {NUMBER} of {NUMBER} runs at the fit and {NUMBER} at the "
                      rf"median draw", [r0.ess, r0.runs, r0.ess_median])
    assert (d.ess == r0.ess).all() and (d.ess_median == r0.ess_median).all()


def test_the_waal_example_as_quoted():
    """docs/your-own-study.md's results of the Waal study: its runs, the
    table per level (results/studies/waal/study/statistics.csv) and the two
    equations with their cross-validated errors (equations.csv)."""
    page = DOCS["docs/your-own-study.md"]
    folder = RESULTS / "studies/waal/study"
    stats = pd.read_csv(folder / "statistics.csv")
    every = stats[stats["mode"] == "all"]
    study = yaml.safe_load((ROOT / "config/studies/waal.yaml").read_text())
    runs = study["samples"] * len(study["sweep"]["levels"])
    assert f"runs the {study['samples']} x {len(study['sweep']['levels'])} = {runs} simulations" in _flat(page)
    assert every.excluded.sum() == 0 and every["count"].sum() == runs
    assert f"all {runs} runs ok" in _flat(page)
    rows = _table(page, "| p | P_max mean, COV |")
    assert len(rows) == len(every)
    for (p, load, strength, brick), r in zip(rows, every.itertuples()):
        assert p == ("0" if r.p_mpa == 0 else f"{r.p_mpa:g} MPa")
        assert load == f"{r.P_max_mean_kN:.2f} kN, {r.P_max_cov:.2f}", (p, load)
        assert strength == f"{r.strength_mean_mpa:.2f} MPa", (p, strength)
        assert brick == f"{round(r.brick_share * r.count)} of {r.count}", (p, brick)
    eqs = pd.read_csv(folder / "equations.csv").set_index("mode")
    assert (f"cross-validated MAPE {eqs.cv_mape_pct['joint']:.1f} % (joint) and {eqs.cv_mape_pct['brick']:.1f} % "
            "(brick)") in _flat(page)
    for mode in ("joint", "brick"):
        assert f"\n{mode}: {eqs.equation[mode]}\n" in page, mode


# --- findings.md: the snap-back hard case ------------------------------------


def test_the_snap_back_case_as_quoted():
    """docs/findings.md's snap-back case `tiny_GI` at the defaults: its
    peak and its unbalance at the peak (results/stability/hard_cases.csv),
    under the 1 % of the peak rule, and below the reference's peak."""
    hard = pd.read_csv(RESULTS / "stability/hard_cases.csv").set_index("run")
    tiny = hard.loc["tiny_GI"]
    text = _flat(DOCS["docs/findings.md"])
    assert (f"At the defaults it peaks at {tiny.P_max_kN:.2f} kN, at an unbalance of {tiny.unbalance_at_peak:.4f}, "
            "just under the 1 % of the peak rule (results/stability/hard_cases.csv)") in text
    assert tiny.unbalance_at_peak < 0.01 and tiny.ok and tiny.failure_mode == "joint"
    assert tiny.P_max_kN < hard.loc["reference"].P_max_kN


# --- the command line as docs/usage.md documents it -------------------------


def test_usage_documents_every_option_of_the_command_line():
    """Every command of `masonrydem` (src/masonrydem/cli.py's parser) has
    its section in docs/usage.md, and every option of it (and the
    program's own, --version) is named there, in that command's section,
    with its default where the parser sets one other than off."""
    import argparse
    from masonrydem.cli import parser
    usage = DOCS["docs/usage.md"]
    p = parser()
    top = [a for a in p._actions if a.option_strings and not isinstance(a, argparse._HelpAction)]
    assert top and all(f"`.venv/bin/masonrydem {a.option_strings[0]}`" in usage for a in top)
    sub = next(a for a in p._actions if isinstance(a, argparse._SubParsersAction))
    assert set(sub.choices) == {"run", "check", "predict", "fit"}
    for name, command in sub.choices.items():
        heading = re.search(rf"^## .*`masonrydem {name}`.*$", usage, re.M)
        assert heading, name
        section = usage[heading.start():usage.find("\n## ", heading.end())]
        for action in command._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            if not action.option_strings:       # a positional argument: its metavar in the section
                shown = action.metavar or action.dest.upper()
                assert f"`{shown}" in section or f"`{action.dest.upper()}" in section, (name, shown)
                continue
            option = action.option_strings[0]
            assert re.search(rf"`{re.escape(option)}[ `]", section), (name, option)
            if action.default not in (None, False, []):
                row = next(r for r in _table(section, "| option | meaning | default |") if option in r[0])
                assert row[2] == f"{action.default}", (name, option, row)


# --- the docs' commands: run from the venv, as the README's ------------------


@pytest.mark.parametrize("page", sorted(DOCS))
def test_the_commands_of_the_docs_run_from_the_venv(page):
    """A command line of a page's code blocks that runs masonrydem,
    Snakemake or Python (with or without a `$ ` prompt, in a loop's body
    too) starts with .venv/bin/, as the README's do, so that it runs as
    written after `make install`."""
    bare = []
    for block in re.findall(r"```[a-z]*\n(.*?)```", DOCS[page], re.S):
        if block.lstrip().startswith(("import ", "from ")):     # a Python example
            continue
        for line in block.splitlines():
            command = line.strip().removeprefix("$ ")
            if re.match(r"(masonrydem|snakemake|python3?) ", command):
                bare.append(line)
    assert not bare, bare


# --- no notebook on the pages -------------------------------------------------

DIARY = re.compile(r"\b(?:was|were) tried\b|\brun by hand\b|\bearlier solver\b|\bnot (?:yet )?examined\b|"
                   r"\bwas removed\b|\bAMD\b|\bEPYC\b|\bwe tried\b")


@pytest.mark.parametrize("page", sorted(DOCS))
def test_the_pages_keep_no_diary(page):
    """The pages state what holds now: no 'was tried', 'run by hand', 'an
    earlier solver', 'was removed', nor the brand of the machine a number
    was measured on (history belongs to CHANGELOG.md and docs/dev/)."""
    found = [m.group(0) for m in DIARY.finditer(_flat(DOCS[page]))]
    assert not found, found


# --- findings.md: the stochastic study and the paper side by side -----------

FINDINGS = _flat(DOCS["docs/findings.md"])


def _cells(cell):
    """The numbers of a table cell written 'a / b / c' (signs and % kept off)."""
    return [x.strip().rstrip("%").strip() for x in cell.split("(")[0].split("/")]


def test_the_studys_table_and_its_runs():
    """docs/findings.md's table of the study per variant and level is
    results/study/statistics.csv's all-mode rows (mean P_max, COV, share
    of brick failures), and its count of how the runs stopped, and of the
    one left out, results/study/runs.parquet's statuses."""
    stats = pd.read_csv(RESULTS / "study/statistics.csv")
    rows = _table(DOCS["docs/findings.md"], "| variant | sigma_v (MPa) | mean P_max (kN) | COV | brick failures |")
    for (variant, levels, means, covs, bricks), (name, g) in zip(rows, stats[stats["mode"] == "all"].groupby(
            "variant", sort=False)):
        assert variant.replace("-", "") == name
        assert _cells(levels) == [f"{v:g}" for v in g.sigma_v_mpa]
        for shown, value in zip(_cells(means), g.P_max_mean_kN):
            assert _agrees(shown, value), (name, shown, value)
        for shown, value in zip(_cells(covs), g.P_max_cov):
            assert _agrees(shown, value), (name, shown, value)
        for shown, value in zip(_cells(bricks), 100 * g.brick_share):
            assert _agrees(shown, value, 2), (name, shown, value)
    status = pd.read_parquet(RESULTS / "study/runs.parquet", columns=["status"]).status.value_counts()
    assert set(status.index) <= {"past_peak", "load_drop", "displacement_limit", "lower_bound"}
    assert (f"Every one of the {status.sum()} runs reached a stop criterion ({status['past_peak']} past the peak once "
            f"it was certain, {status['load_drop']} on the load drop, "
            f"{status['displacement_limit'] + status.get('lower_bound', 0)} at the 1 mm displacement limit). "
            f"One of the {status['displacement_limit'] + status.get('lower_bound', 0)}, non-spatial at 0.5 MPa, "
            "stopped too soon after its peak") in FINDINGS
    excluded = stats[(stats["mode"] == "all") & (stats.excluded > 0)]
    assert status.get("lower_bound", 0) == 1 == excluded.excluded.sum()
    assert excluded.variant.iloc[0] == "nonspatial" and excluded.sigma_v_mpa.iloc[0] == 0.5


def test_the_studys_equations_and_fractiles_as_quoted():
    """docs/findings.md's prediction equations with their runs and errors
    (results/study/equations.csv) and its characteristic strengths of the
    non-spatial wallette (characteristic.csv)."""
    eqs = pd.read_csv(RESULTS / "study/equations.csv").set_index("mode")
    for mode in ("joint", "brick"):
        assert f"- {mode} failure ({eqs.n[mode]} runs): {_flat(eqs.equation[mode])}" in FINDINGS, mode
    low = eqs.loc["lower of two"]
    assert (f"Their out-of-fold mean absolute percentage errors are {eqs.cv_mape_pct['joint']:.1f} % and "
            f"{eqs.cv_mape_pct['brick']:.1f} %. The lower of the two scores {low.mape_pct:.1f} % and names the "
            f"failure mode correctly in {100 * low.mode_agreement:.0f} % of the runs") in FINDINGS
    c = pd.read_csv(RESULTS / "study/characteristic.csv")
    c = c[c.variant == "nonspatial"].set_index("sigma_v_mpa")
    _numbers_as(FINDINGS, rf"The non-spatial wallette: \*\*{NUMBER} MPa \({NUMBER} to {NUMBER}\)\*\* at 0 MPa, {NUMBER} "
                          rf"MPa at 0.15 MPa and {NUMBER} MPa \({NUMBER} to {NUMBER}\) at 0.5 MPa",
                [c.characteristic_mpa[0], c.lognormal_mpa_lo[0], c.lognormal_mpa_hi[0], c.characteristic_mpa[0.15],
                 c.characteristic_mpa[0.5], c.lognormal_mpa_lo[0.5], c.lognormal_mpa_hi[0.5]])
    assert (c.supported == "lognormal").all()


def test_the_sobol_check_as_quoted():
    """docs/findings.md's study indices against the direct ones at the
    check's level (results/sobol_check/check.csv), its runs and base
    points, and its cost (timing.csv)."""
    check = pd.read_csv(RESULTS / "sobol_check/check.csv").set_index("input")
    timing = pd.read_csv(RESULTS / "sobol_check/timing.csv").iloc[0]
    assert (f"({timing.runs:.0f} runs, Saltelli's pick-freeze scheme on {timing.base:.0f} base points;" in FINDINGS)
    assert check.S1_inside.all() and check.ST_inside.all()
    assert f"All {WORDS[2 * len(check)]} of the study's indices there" in FINDINGS
    for name, words in (("f_tj_mpa", "f_tj's total index"), ("f_tu_mpa", "f_tu's"), ("E_b_mpa", "E_b's"),
                        ("phi_j_deg", "phi_j's")):
        r = check.loc[name]
        _numbers_as(FINDINGS, rf"{re.escape(words)} {NUMBER} against {NUMBER} \({NUMBER} to {NUMBER}\)",
                    [r.ST_study, r.ST_direct, r.ST_direct_lo, r.ST_direct_hi])
    assert (f"The check's {timing.batches:.0f} batches cost {timing.batch_core_s / 60:.0f} minutes of one core, summed"
            in FINDINGS)


def test_the_paper_side_by_side_as_quoted():
    """docs/findings.md's table of the paper beside the study and the
    sentences that read it are results/study/paper_comparison.csv's."""
    p = PAPER.copy()

    def rows(item, mode):
        return p[(p["item"] == item) & (p["mode"] == mode)].sort_values("sigma_v_mpa")
    table = {r[0]: r[1:] for r in _table(DOCS["docs/findings.md"], "| figure | paper | this study |")}
    means = rows("F_max mean (kN)", "all")
    paper, ours = table["all-data mean F_max, 0 / 0.075 / 0.15 / 0.25 / 0.5 MPa (kN)"]
    for shown, v in zip(_cells(paper), means.paper):
        assert _agrees(shown, v), shown
    for shown, v in zip(_cells(ours), means.ours):
        assert _agrees(shown, v), shown
    for label, mode in (("joint-mode mean, same levels (kN)", "joint"), ("brick-mode mean, same levels (kN)", "brick")):
        m = rows("F_max mean (kN)", mode)
        paper, ours = table[label]
        assert all(_agrees(s, v) for s, v in zip(_cells(paper), m.paper)), label
        assert _cells(ours) == [f"{d:+.1f}" for d in m.difference_pct], (label, ours)
    inside = p[p["item"] == "F_max mean (kN)"]
    assert table["published means inside the study's intervals"][1] == f"{inside.paper_inside.sum()} of {len(inside)}"
    covs = p[p["item"] == "F_max COV"]
    assert table["published COVs inside the study's intervals"][1] == f"{covs.paper_inside.sum()} of {len(covs)}"
    fails = p[p["item"].str.startswith("failures")].set_index("mode")
    _numbers_as(" ".join(table["failures, joint / brick (of 500)"]),
                rf"{NUMBER} / {NUMBER} {NUMBER} / {NUMBER} \({NUMBER}-{NUMBER} / {NUMBER}-{NUMBER}\)",
                [fails.paper["joint"], fails.paper["brick"], fails.ours["joint"], fails.ours["brick"],
                 fails.ours_lo["joint"], fails.ours_hi["joint"], fails.ours_lo["brick"], fails.ours_hi["brick"]])
    on_ours = p[p["item"].str.startswith("Eq. 10 on our runs")].set_index(["item", "mode"])
    bias = on_ours.loc[("Eq. 10 on our runs: bias (%)", "lower of two")]
    mape = on_ours.loc[("Eq. 10 on our runs: MAPE (%)", "lower of two")]
    _numbers_as(table["the paper's Eq. 10 on the study's runs: bias, MAPE"][1],
                rf"-{NUMBER} % \(-{NUMBER} to -{NUMBER}\), {NUMBER} %",
                [-bias.ours, -bias.ours_lo, -bias.ours_hi, mape.ours])
    coef = p[(p["item"] == "Eq. 10 coefficient: sigma_v") & (p["mode"] == "joint")].iloc[0]
    paper, ours = table["joint-mode sigma_v coefficient"]
    assert _agrees(paper, coef.paper)
    _numbers_as(ours, rf"{NUMBER} \({NUMBER} to {NUMBER}\)", [coef.ours, coef.ours_lo, coef.ours_hi])
    _numbers_as(FINDINGS, rf"joint mode's sigma_v term, {NUMBER} \({NUMBER} to {NUMBER}\) against {NUMBER}",
                [coef.ours, coef.ours_lo, coef.ours_hi, coef.paper])
    for m in re.finditer(rf"the study's sigma_v coefficient {NUMBER} against {NUMBER}", FINDINGS):
        assert _agrees(m.group(1), coef.ours) and _agrees(m.group(2), coef.paper), m.group(0)
    # the sentences after the table
    rise = p[p["item"].str.startswith("increase")].set_index("mode")
    _numbers_as(FINDINGS, rf"The increase of the all-data mean from 0 to 0.5 MPa: \+{NUMBER} % \(\+{NUMBER} to "
                          rf"\+{NUMBER}\) against \+{NUMBER} %. Brick mode: \+{NUMBER} % \(-{NUMBER} to \+{NUMBER}\) "
                          rf"against \+{NUMBER} %",
                [rise.ours["all"], rise.ours_lo["all"], rise.ours_hi["all"], rise.paper["all"], rise.ours["brick"],
                 -rise.ours_lo["brick"], rise.ours_hi["brick"], rise.paper["brick"]])
    _numbers_as(FINDINGS, rf"The joint-mode increase from 0 to 0.5 MPa agrees with this: \+{NUMBER} % \(\+{NUMBER} to "
                          rf"\+{NUMBER}\) against \+{NUMBER} %",
                [rise.ours["joint"], rise.ours_lo["joint"], rise.ours_hi["joint"], rise.paper["joint"]])
    own = p[p["item"] == "Eq. 10 MAPE (%)"].iloc[0]
    _numbers_as(FINDINGS, rf"MAPE \(the study's {NUMBER} %, {NUMBER} to {NUMBER}, against {NUMBER} %\)",
                [own.ours, own.ours_lo, own.ours_hi, own.paper])
    run = p[p["item"].str.startswith("running mean")].iloc[0]
    assert f"from run {run.ours:.0f} on (the paper: it stabilises after about {run.paper:.0f};" in FINDINGS
    joint = on_ours.loc[("Eq. 10 on our runs: bias (%)", "joint")]
    brick = on_ours.loc[("Eq. 10 on our runs: bias (%)", "brick")]
    assert (f"underpredicts the study's runs by {-bias.ours:.1f} % on average: by {-joint.ours:.1f} % in joint mode "
            f"and {-brick.ours:.1f} % in brick mode") in FINDINGS
    jm = rows("F_max mean (kN)", "joint")
    assert (f"from {jm.difference_pct.iloc[0]:+.1f} % at 0 MPa to {jm.difference_pct.iloc[-1]:+.1f} % at 0.5 MPa"
            in FINDINGS)
    eq = p[p["item"] == "equation at the mean properties: P_max (kN)"]
    j, b = eq[eq["mode"] == "joint"].sort_values("sigma_v_mpa"), eq[eq["mode"] == "brick"].sort_values("sigma_v_mpa")
    assert (f"give {j.difference_pct.iloc[0]:.0f} % (0 MPa) to {j.difference_pct.iloc[-1]:.0f} % (0.5 MPa) more than "
            f"the paper's in joint mode ({j.ours.iloc[0]:.2f} against {j.paper.iloc[0]:.2f} kN at 0 MPa) and "
            f"{b.difference_pct.min():.0f} to {b.difference_pct.max():.0f} % more in brick mode "
            f"({b.ours.iloc[0]:.2f} against {b.paper.iloc[0]:.2f} kN at 0 MPa)") in FINDINGS


def test_the_sobol_method_as_described():
    """docs/study.md 12a's base points, posterior draws, random features and
    the runs the process's parameters are fitted to at most, against
    analysis/sensitivity.py's constants."""
    from masonrydem.analysis import sensitivity as S
    text = _flat(_section(DOCS["docs/study.md"], "## 12a."))
    _numbers_as(text, rf"Sobol sequence with {NUMBER} base points", [S.N_BASE])
    _numbers_as(text, rf"{NUMBER} functions drawn from the process's posterior \(a prior draw by {NUMBER} random "
                      rf"Fourier features", [S.DRAWS, S.FEATURES])
    _numbers_as(text, rf"Where a group has more than {NUMBER} runs, the kernel's parameters are fitted to {NUMBER} of "
                      rf"them", [S.FIT_RUNS, S.FIT_RUNS])


def test_the_sobol_indices_as_quoted():
    """docs/findings.md's reading of the study's Sobol indices
    (results/study/sensitivity.csv, the non-spatial variant, all modes):
    the surrogate's leave-one-out R^2, the total indices of f_tj and f_tu
    at the lowest and highest level, both at 0.25 MPa, E_b's range and its
    squared correlation, and the first-order indices' sums."""
    s = pd.read_csv(RESULTS / "study/sensitivity.csv")
    s = s[(s.variant == "nonspatial") & (s["mode"] == "all")]
    st = s.pivot(index="sigma_v_mpa", columns="input", values="ST")
    lo = s.pivot(index="sigma_v_mpa", columns="input", values="ST_lo")
    hi = s.pivot(index="sigma_v_mpa", columns="input", values="ST_hi")
    first, last = st.index.min(), st.index.max()
    _numbers_as(FINDINGS, rf"leave-one-out R\^2 {NUMBER} to {NUMBER},", [s.cv_r2.min(), s.cv_r2.max()])
    _numbers_as(FINDINGS, rf"The total index of f_tj falls from {NUMBER} \({NUMBER} to {NUMBER}\) at 0 MPa to {NUMBER} "
                          rf"\({NUMBER} to {NUMBER}\) at 0.5 MPa, and f_tu's rises from {NUMBER} to {NUMBER} \({NUMBER} "
                          rf"to {NUMBER}\). At 0.25 MPa the two share the variance: {NUMBER} and {NUMBER},",
                [st.f_tj_mpa[first], lo.f_tj_mpa[first], hi.f_tj_mpa[first], st.f_tj_mpa[last], lo.f_tj_mpa[last],
                 hi.f_tj_mpa[last], st.f_tu_mpa[first], st.f_tu_mpa[last], lo.f_tu_mpa[last], hi.f_tu_mpa[last],
                 st.f_tj_mpa[0.25], st.f_tu_mpa[0.25]])
    assert st.f_tj_mpa[0.25] + st.f_tu_mpa[0.25] > 1
    squared = s[(s.sigma_v_mpa == last) & (s.input == "E_b_mpa")].pearson_sq.iloc[0]
    _numbers_as(FINDINGS, rf"E_b's total index stays at {NUMBER} to {NUMBER}, although its squared correlation with the "
                          rf"strength reaches {NUMBER} at 0.5 MPa",
                [st.E_b_mpa.min(), st.E_b_mpa.max(), squared])
    _numbers_as(FINDINGS, rf"phi_j drives at most {NUMBER}\.", [st.phi_j_deg.max()])
    sums = s.groupby("sigma_v_mpa").S1.sum()
    _numbers_as(FINDINGS, rf"The first-order indices sum to {NUMBER} \(at {NUMBER} MPa\) to {NUMBER}:",
                [sums.min(), sums.idxmin(), sums.max()])


def test_the_studys_bullets_as_quoted():
    """docs/findings.md's bullets on the study: the rise of the mean with
    the precompression (results/study/increase.csv), the brick shares at
    0.15 MPa (statistics.csv), the correlations (correlations.csv) and the
    design rules beside the simulated mean (design_comparison.csv)."""
    inc = pd.read_csv(RESULTS / "study/increase.csv").query("mode == 'all'").set_index("variant")
    assert (f"raises the mean P_max from 0 to 0.5 MPa by {100 * inc.increase['nonspatial']:.0f} % (non-spatial) and "
            f"{100 * inc.increase['spatial']:.0f} % (spatial)") in FINDINGS
    stats = pd.read_csv(RESULTS / "study/statistics.csv").query("mode == 'all' and sigma_v_mpa == 0.15")
    share = stats.set_index("variant").brick_share
    assert (f"({100 * share['spatial']:.0f} % brick failures against {100 * share['nonspatial']:.0f} % at 0.15 MPa)"
            in FINDINGS)
    corr = pd.read_csv(RESULTS / "study/correlations.csv").query("mode == 'all'")
    ns = corr[corr.variant == "nonspatial"].set_index("sigma_v_mpa")
    _numbers_as(FINDINGS, rf"\(r = \+{NUMBER} at 0 MPa\) and the units' f_tu at high precompression \(r = \+{NUMBER} at "
                          rf"0.5 MPa, against \+{NUMBER} for f_tj\); E_b's correlation grows with the precompression "
                          rf"\(\+{NUMBER} to \+{NUMBER}\)",
                [ns.f_tj_mpa[0], ns.f_tu_mpa[0.5], ns.f_tj_mpa[0.5], ns.E_b_mpa.min(), ns.E_b_mpa.max()])
    sp = corr[corr.variant == "spatial"].set_index("sigma_v_mpa")[["f_tj_mpa", "f_tu_mpa", "phi_j_deg", "E_b_mpa"]]
    band = 1.96 / math.sqrt(100)
    assert f"all lie within +-{band:.2f}, the 5 % band for 100 runs" in FINDINGS
    outside = sp[sp.abs() > band].stack().dropna()
    assert list(outside.index) == [(0.25, "phi_j_deg"), (0.5, "phi_j_deg")], outside
    _numbers_as(FINDINGS, rf"except phi_j at 0.25 and 0.5 MPa \(-{NUMBER} and -{NUMBER}\)", list(-outside))
    d = pd.read_csv(RESULTS / "study/design_comparison.csv").set_index("sigma_v_mpa")
    mean0 = pd.read_csv(RESULTS / "study/statistics.csv").query(
        "mode == 'all' and variant == 'nonspatial'").set_index("sigma_v_mpa").strength_mean_mpa
    _numbers_as(FINDINGS, rf"Design rules\*\* at 0 MPa: the simulated mean strength is {NUMBER} MPa; the Lourenco-Gaetani "
                          rf"bounds give {NUMBER} MPa \(stepped\) and {NUMBER} MPa \(brick\), AS3700 {NUMBER} MPa "
                          rf"\(stepped\) and {NUMBER} MPa \(line\). The prediction at the mean properties \({NUMBER} MPa "
                          rf"at 0.25 MPa\) lies above the simulated mean \({NUMBER} MPa\)",
                [mean0[0], d.lg_stepped[0], d.lg_brick[0], d.as3700_stepped[0], d.as3700_line[0], d.prediction[0.25],
                 mean0[0.25]])
    _numbers_as(FINDINGS, rf"the mean of the prediction over the sampled properties, {NUMBER} MPa, matches the simulated "
                          rf"mean, within {NUMBER} % at every level", [d.mean_over_samples[0.25], 0.8])
    for level in (0, 0.15, 0.25, 0.5):
        assert abs(d.mean_over_samples[level] / mean0[level] - 1) <= 0.008, level


# --- docs/study.md, formulation.md, known-problems.md, lab-to-design.md: single numbers ---


def test_e_bs_independent_index_as_quoted():
    """docs/study.md's E_b at 0.5 MPa: its squared correlation with the
    strength and its total index (results/study/sensitivity.csv, the
    non-spatial variant, all modes: pearson_sq and ST)."""
    s = pd.read_csv(RESULTS / "study/sensitivity.csv")
    e = s[(s.variant == "nonspatial") & (s["mode"] == "all") & (s.input == "E_b_mpa") & (s.sigma_v_mpa == 0.5)].iloc[0]
    _numbers_as(_flat(DOCS["docs/study.md"]), rf"at 0.5 MPa, E_b's squared correlation with the strength is {NUMBER}, "
                                              rf"yet its total index is only {NUMBER}\.", [e.pearson_sq, e.ST])


def _fewest_runs_with_a_lower_end(p=0.05, tail=0.025):
    """The smallest n with (1 - p)^n <= tail: below it all n runs lie above
    the p-fractile with a probability above the interval's tail, so no
    order statistic bounds the fractile from below (closed form)."""
    return math.ceil(math.log(tail) / math.log(1 - p) - 1e-12)


def test_the_order_statistics_as_quoted():
    """docs/study.md's order statistics of the 5 % fractile (95 %
    interval): the runs below which none bounds it from below, (1 - 0.05)^n
    <= 0.025 in closed form, as study.md and lab-to-design.md (the weighted
    order statistics, at equal weights the same rule) state it, and as
    `masonrydem check` and fractiles.order_ranks use it; the ranks and
    coverage for 100 runs from the binomial distribution."""
    from scipy import stats
    from masonrydem.analysis.fractiles import order_ranks
    from masonrydem.analysis.needs import lower_end_runs
    n = _fewest_runs_with_a_lower_end()
    assert 0.95 ** n <= 0.025 < 0.95 ** (n - 1)
    assert n == lower_end_runs() and order_ranks(n)[0] == 1 and order_ranks(n - 1)[0] is None
    study = _flat(DOCS["docs/study.md"])
    assert (f"Below {n} runs no order statistic bounds the 5 % fractile from below: all n runs lie above the fractile "
            f"with probability 0.95^n, which falls to the interval's 2.5 % only at n = {n}.") in study
    design = _flat(DOCS["docs/lab-to-design.md"])
    assert (f"below {n} runs no run bounds the 5 % fractile from below (at equal weights all n runs lie above it with "
            f"probability 0.95^n, more than the interval's 2.5 % below n = {n})") in design
    cdf = stats.binom.cdf(np.arange(101), 100, 0.05)
    r = int(np.flatnonzero(cdf <= 0.025)[-1]) + 1
    s = int(np.flatnonzero(cdf >= 0.975)[0]) + 1
    ordinal = {1: "1st", 2: "2nd", 3: "3rd"}
    assert (f"For 100 runs these are the {ordinal.get(r, f'{r}th')} and {ordinal.get(s, f'{s}th')} smallest values, "
            f"with coverage {100 * (cdf[s - 1] - cdf[r - 1]):.1f} %.") in study


def test_the_self_weight_as_quoted():
    """docs/study.md's self-weight stress at the wallette's base: rho g H
    with the units' density and the height of config/scenes/willis.yaml's
    courses (a modelled unit: the brick and a joint), in kPa."""
    scene = yaml.safe_load((ROOT / "config/scenes/willis.yaml").read_text())
    g = scene["geometry"]
    height = g["courses"] * (g["unit"]["height"] + g["joint_thickness"])
    kpa = scene["materials"]["units"]["density"] * 9.81 * height / 1e3
    assert scene["physics"]["gravity"] is False
    assert f"(rho g H: the units' density, the wallette's height), about {kpa:.0f} kPa, is negligible" in \
        _flat(DOCS["docs/study.md"])


def test_the_lasso_check_as_quoted():
    """docs/study.md's agreement of the exact Lasso path with scikit-learn's
    LassoCV is what tests/test_regression.py asserts: coordinate descent to
    a duality gap of 1e-12, the penalty to 1e-12 relative, the coefficients
    within 1e-7 of the largest."""
    source = (ROOT / "tests/test_regression.py").read_text()
    assert "LassoCV(cv=cv, max_iter=10_000_000, tol=1e-12)" in source
    assert "fit.alpha == pytest.approx(ref.alpha_, rel=1e-12)" in source
    assert "atol=1e-7 * max(np.abs(ref.coef_).max()" in source
    assert ("Against scikit-learn's `LassoCV` (coordinate descent to a duality gap of 1e-12, on the same folds) it gives "
            "the same penalty to 1e-12 relative and the coefficients within 1e-7 of the largest "
            "(tests/test_regression.py, on constructed runs)") in _flat(DOCS["docs/study.md"])


def test_the_head_joint_refinement_as_quoted():
    """docs/formulation.md's effect of the head joints' refinement: the
    error of joint_sv05 on 4x3x2 cells without it (pc_c4x3x2_r1) and with
    it (the defaults), and on 6x3x2 cells the largest change of P_max from
    refining every joint (pc_c6x3x2_r121) against the head joints alone
    (pc_c6x3x2_head), rounded up to 0.1 % (results/accuracy/runs.csv)."""
    error = RUNS.set_index(["setting", "case"]).error
    text = _flat(DOCS["docs/formulation.md"])
    assert (f"the weak-joint accuracy case, joint_sv05, moved from {100 * error['pc_c4x3x2_r1', 'joint_sv05']:+.1f} % "
            f"to {100 * error['default', 'joint_sv05']:+.1f} % with it on 4x3x2 cells") in text
    p = RUNS.pivot(index="case", columns="setting", values="P_max_kN")
    change = (p.pc_c6x3x2_r121 / p.pc_c6x3x2_head - 1).abs().max()
    assert len(p) == 5 and (RUNS.set_index("setting").loc["default"].cells == "4x3x2").all()
    assert (f"on 6x3x2 cells, refining the bed joints and the crack interfaces too changed no case by more than "
            f"{math.ceil(1000 * change) / 10:.1f} %") in text


def test_the_rate_error_per_component_as_quoted():
    """docs/formulation.md's loading-rate error of the defaults in brick
    failure: P_max against the linear extrapolation to zero rate from the
    run at half the rate, 2 P(r/2) - P(r) (results/accuracy/runs.csv,
    default and rate_3.75e-08, half the scene's rate)."""
    p = RUNS.set_index(["setting", "case"]).P_max_kN
    half = "rate_3.75e-08"
    assert 2 * float(half.split("_")[1]) == pytest.approx(float(_default("loading", "bending", "rate")))

    def error(case):
        return 100 * (p["default", case] / (2 * p[half, case] - p["default", case]) - 1)
    assert (f"results/accuracy/runs.csv) is {error('brick_sv0'):+.1f} % at 0 MPa and {error('brick_sv05'):+.1f} % at "
            "0.5 MPa") in _flat(DOCS["docs/formulation.md"])


def test_the_weakest_joints_half_rate_peak_as_quoted():
    """docs/formulation.md's hard case ftj_0.05: its peak at the defaults
    above its half-rate rerun's (results/stability/hard_cases.csv), under
    the peak judge's 1 % (history.PEAK_UNBALANCE)."""
    hard = pd.read_csv(RESULTS / "stability/hard_cases.csv").set_index("run").P_max_kN
    above = 100 * (hard["ftj_0.05"] / hard["ftj_0.05_half_rate"] - 1)
    limit = re.search(r"^PEAK_UNBALANCE = ([\d.]+)", (SRC / "dem/history.py").read_text(), re.M).group(1)
    assert (f"(f_tj = 0.05 MPa, hard case `ftj_0.05`), whose early peak rings, read {above:.1f} % above their half-rate "
            f"peak at {100 * float(limit):g} % (results/stability/hard_cases.csv)") in _flat(DOCS["docs/formulation.md"])


def test_the_lower_bounds_share_as_quoted():
    """docs/formulation.md's share of runs with a lower bound only: under
    1 % in every committed study (its runs.parquet's status)."""
    files = [RESULTS / "study/runs.parquet", *sorted((RESULTS / "studies").glob("**/study/runs.parquet"))]
    assert len(files) > 1
    for f in files:
        status = pd.read_parquet(f, columns=["status"]).status
        assert (status == "lower_bound").mean() < 0.01, f
    assert "the committed studies have such runs in under 1 % of their runs" in _flat(DOCS["docs/formulation.md"])


def test_the_mislabelled_path_level_as_quoted():
    """docs/known-problems.md's brick_sv0 path level 19x9x7: its P_max and
    its neighbours', its joint label against their brick ones, and its stop
    on the load drop (results/accuracy/references.csv)."""
    ref = pd.read_csv(RESULTS / "accuracy/references.csv")
    path = ref[(ref.case == "brick_sv0") & ref.setting.str.startswith("path_c")].set_index("cells")
    lone, below, above = (path.loc[c] for c in ("19x9x7", "17x8x6", "21x10x8"))
    assert lone.failure_mode == "joint" and below.failure_mode == above.failure_mode == "brick"
    assert lone.status == "load_drop"
    _numbers_as(_flat(DOCS["docs/known-problems.md"]),
                rf"brick_sv0 on 19x9x7 cells \(results/accuracy/runs.csv\) peaks at {NUMBER} kN, in line with its "
                rf"neighbours \({NUMBER} and {NUMBER} kN\), but is labelled a joint failure",
                [lone.P_max_kN, below.P_max_kN, above.P_max_kN])


def test_the_vertex_rule_as_quoted():
    """docs/known-problems.md's vertex rule at the safety factor 0.5 on the
    mean-property wallette at 0 MPa (results/modelform/summary.csv, the
    joint case): its status, P_max and change from the baseline; the
    default safety factor it rings at is the schema's, and the model-form
    study runs the rule at 0.5 (config/config.yaml)."""
    m = pd.read_csv(RESULTS / "modelform/summary.csv")
    v = m[(m.case == "joint") & (m.sigma_v_mpa == 0) & (m.option == "vertices (3DEC), safety 0.5")].iloc[0]
    assert v.status == "load_drop"
    text = _flat(DOCS["docs/known-problems.md"])
    _numbers_as(text, rf"At the safety factor 0.5 the run ends on its load drop, at a P_max of {NUMBER} kN "
                      rf"\(results/modelform/summary.csv, joint case at 0 MPa\), {NUMBER} % above the baseline's",
                [v.P_max_kN, v.change_pct])
    safety = SCHEMA["properties"]["numerics"]["properties"]["safety"]["default"]
    assert f"the default safety factor {safety:g}, the mean-property wallette" in text
    rule = next(a for a in CONFIG["modelform"]["assumptions"] if a["name"] == "subcontact_rule")
    assert any("numerics.safety=0.5" in o["overrides"] and "numerics.subcontact_rule=vertices" in o["overrides"]
               for o in rule["options"])
    assert next(c for c in CONFIG["modelform"]["cases"] if c["name"] == "joint")["overrides"] == []


def test_the_design_rerun_sentence_as_quoted():
    """docs/lab-to-design.md's sentence on the solver reruns: the largest
    distance of a re-weighted fractile from its rerun's
    (results/studies/waal_lab/design/rerun.csv), that pair, where it lies
    (the lab-only interval's upper end) and its ESS of the study's runs
    (design.csv)."""
    t = pd.read_csv(RESULTS / "studies/waal_lab/design/rerun.csv")
    diff = (t.reweighted_mpa / t.rerun_mpa - 1).abs()
    worst = t.loc[diff.idxmax()]
    runs = pd.read_csv(RESULTS / "studies/waal_lab/design/design.csv").runs.iloc[0]
    assert worst.lab_quantile == 97.5
    assert t.inside.all()
    assert (f"within {100 * diff.max():.2f} % of the rerun's own fractile ({worst.reweighted_mpa:.3f} against "
            f"{worst.rerun_mpa:.3f} MPa at the upper end of the lab-only interval, where the weighted runs are worth "
            f"{worst.ess:.0f} of {runs})") in _flat(DOCS["docs/lab-to-design.md"])


def test_the_design_coverage_limit_as_quoted():
    """docs/lab-to-design.md's coverage check is tests/test_design.py's: 300
    labs and studies per case, each side's misses at most the binomial
    (300, 2.5 %) count at 99.9 %, computed here."""
    from scipy import stats
    source = (ROOT / "tests/test_design.py").read_text()
    assert source.count("stats.binom.ppf(0.999, 300, 0.025)") >= 2
    limit = stats.binom.ppf(0.999, 300, 0.025)
    text = _flat(DOCS["docs/lab-to-design.md"])
    assert "tests/test_design.py draws 300 labs and studies per case" in text
    assert f"on each side at most the binomial limit of 2.5 % ({limit:.0f} of 300, at 99.9 %)" in text


def test_the_agreement_tests_power_as_quoted():
    """docs/lab-to-design.md's size and power of the wallette tests'
    agreement test are what tests/test_directions.py asserts: 5 tests among
    20 runs a level over 2000 constructed cases, called in disagreement at
    most as often as the binomial (2000, 5 %) allows at 99.9 %, and tests
    30 % stronger found in at least half of them."""
    source = (ROOT / "tests/test_directions.py").read_text()
    for piece in ("for _ in range(2000):", "_runs(rng, levels, 20)", "rng.choice(levels, 5)", "1.3e6 * x",
                  "hits / 2000 <= stats.binom.ppf(0.999, 2000, 0.05) / 2000", "found / 2000 >= 0.5"):
        assert piece in source, piece
    assert ("with 5 tests among 20 runs a level, over 2000 constructed cases, tests drawn from the prediction itself "
            "are called in disagreement no more often than the binomial limit of a 5 % test allows (the test is exact), "
            "and tests 30 % stronger than the prediction are found in at least half") in _flat(DOCS["docs/lab-to-design.md"])


# --- the commands' printed output, as the pages print it -------------------------


def _printed(page, command):
    """(argv, lines) of each code block of page that starts with the command
    line `$ .venv/bin/masonrydem <command> ...` and shows what it prints."""
    import shlex
    blocks = []
    for block in re.findall(r"```\n(\$ \.venv/bin/masonrydem [^\n]*)\n(.*?)```", DOCS[page], re.S):
        line = block[0].removeprefix("$ .venv/bin/masonrydem ")
        if line.split()[0] == command:
            blocks.append((shlex.split(line, comments=True), block[1].splitlines()))
    return blocks


def _run_printed(argv, monkeypatch, capsys):
    from masonrydem.cli import main
    monkeypatch.chdir(ROOT)
    capsys.readouterr()
    assert main(argv) == 0, argv
    return capsys.readouterr().out.splitlines()


def test_the_predict_example_prints_as_shown(monkeypatch, capsys):
    """docs/your-own-study.md's `masonrydem predict` block is what the
    command prints on results/studies/waal/study/predictor.json, line for
    line (strengths, interval, load, shear span)."""
    (argv, shown), = _printed("docs/your-own-study.md", "predict")
    assert _run_printed(argv, monkeypatch, capsys) == shown


def test_the_fit_examples_print_as_shown(monkeypatch, capsys):
    """docs/lab-to-design.md's two `masonrydem fit` blocks are what the
    command prints on the committed lab sheets, line for line, up to the
    provenance the page elides ('provenance: ...')."""
    blocks = _printed("docs/lab-to-design.md", "fit")
    assert len(blocks) == 2
    for argv, shown in blocks:
        assert shown[-1].endswith("provenance: ..."), shown[-1]
        out = _run_printed(argv, monkeypatch, capsys)
        assert out[:len(shown) - 1] == shown[:-1], argv
        assert out[len(shown) - 1] == shown[-1].removesuffix(" ..."), argv


# --- the cluster profile's runtimes ------------------------------------------------


def test_the_cluster_profiles_runtimes_cover_the_slowest_runs():
    """profiles/slurm/config.yaml's 'slowest N s (table)' of each rule is
    that committed table's longest wall time, and the rule's runtime is at
    least twice it (the profile's rule)."""
    text = (ROOT / "profiles/slurm/config.yaml").read_text()
    resources = yaml.safe_load(text)["set-resources"]
    body = text[text.index("set-resources:"):]
    checked = set()
    for rule, res in resources.items():
        start = body.index(f"\n  {rule}:\n")
        end = re.search(r"\n  [a-z_]+:\n|\n[^ \n]", body[start + 1:])
        block = body[start:start + 1 + end.start()] if end else body[start:]
        comments = _flat(" ".join(line.split("#", 1)[1] for line in block.splitlines() if "#" in line))
        m = re.search(r"slowest (\d+) s \((?:[^()]*?, )?(results/[\w/]+\.csv)\)", comments)
        if not m:
            continue
        table = m.group(2)
        t = pd.read_csv(ROOT / table)
        times = t[t.against == "units"].run_time_s if "against" in t else t.wall_time_s
        assert m.group(1) == f"{times.max():.0f}", (rule, m.group(0), times.max())
        minutes = int(re.match(r"\s*(\d+)", str(res["runtime"])).group(1))
        assert 60 * minutes >= 2 * times.max(), (rule, minutes, times.max())
        checked.add(rule)
    assert checked == {"validation_run", "hard_case_run", "reduced_run", "specimen_run", "accuracy_run",
                       "accuracy_scaling_run"}, checked


def test_the_strip_resultants_table():
    """docs/findings.md's table of the translating strips' resultants is
    results/modelform/strip_resultants.csv (benchmarks/strip_resultants.py):
    P_max, the arm and the moment per width, the moment within 1 %, and the
    turning strips' resultants within 0.1 mm of their lines."""
    t = pd.read_csv(RESULTS / "modelform/strip_resultants.csv")
    assert set(t.settings) == {"numerics.cells=[6, 3, 2]"}
    text = DOCS["docs/findings.md"]
    assert 'benchmarks/strip_resultants.py --set "numerics.cells=[6, 3, 2]"` measured where' in _flat(text)
    rows = _table("\n".join(x.strip() for x in text.splitlines()), "| strip width | P_max 0 MPa (kN) |")
    moving = t[t.strips == "translate"]
    assert [r for r in rows] == [[f"{w:.0f} mm", f"{p:.3f}", f"{a:.1f}", f"{m:.0f}"] for w, p, a, m in
                                 zip(moving.width_mm, moving.P_max_kN, moving.arm_mm, moving.moment_kN_mm)]
    assert moving.moment_kN_mm.max() / moving.moment_kN_mm.min() - 1 < 0.01
    turning = t[t.strips == "turn"]
    assert list(turning.width_mm) == list(moving.width_mm)
    assert (f"every resultant lies within {turning.max_shift_mm.max():.1f} mm of its line for "
            f"{', '.join(f'{w:.0f}' for w in turning.width_mm[:-1])} and {turning.width_mm.iloc[-1]:.0f} mm") \
        in _flat(text)
