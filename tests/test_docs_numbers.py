"""The numbers the README and docs/ quote against the tables and the config
they come from.  Each test reads the number as the text states it and the
true one from its source (results/**.csv, config/*.yaml, the scene schema,
the package's sources), so that a rerun or a changed setting not carried
into the docs fails here.  Measured times live in one place, the README's
set-up table; the performance log (docs/dev/) and CHANGELOG.md are history
and are not checked.  Fast: no simulation, no import of the solver."""
import re
from pathlib import Path

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
    assert {"`make reproduce` (all but the accuracy study)", "`make test`", "the smoke run (below), from empty"} <= set(TIMES)
    for shown in TIMES.values():
        assert re.fullmatch(r"(\d+ min )?\d+(\.\d)? (s|min)", shown), shown


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
    scaling = pd.read_csv(RESULTS / "accuracy/scaling.csv").set_index(["against", "quantity"])
    units = scaling.loc[("units", "wall_time_s")]
    seconds = [float(p.split(":")[1]) for p in units.points.split()]
    assert [int(p.split(":")[0]) for p in units.points.split()] == [24, 48, 96]
    assert (f"(6, 12, 24 courses: {', '.join(f'{t:.1f}' for t in seconds)} s a run at the defaults, exponent "
            f"{units.exponent:.2f};" in acc)
    assert f"as (cells along the unit)^{scaling.loc[('cells', 'wall_time_s')].exponent:.1f}." in acc


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
