"""Study by study, table by table, a reproduction's results against the
committed ones: the step of `make reproduce` that says whether it
reproduced them.

    python tools/compare_results.py results reproduction/results

The committed folder says what is expected.  Its studies are the folder
itself (the main workflow's results) and every folder below it that holds
study/runs.parquet (a further study's results, made by its own workflow
config: results/studies/nf, .../formats/uk, ...); each is compared with
the folder at the same place in the reproduction.  Walking the committed
folder, rather than a list kept here, compares a newly committed study
without a change to this tool.

In each study, every table below that the committed study holds:

- the tables of single runs (the study's runs.parquet, the validation,
  hard cases, reduced models, specimens, model-form and accuracy tables,
  the Sobol check's runs):
  runs matched by their keys, P_max, the step count, the failure mode and
  the status compared exactly, at the precision the table is written with
  (full for runs.parquet, the CSV's digits for the others).  Wall times
  are not compared;
- the tables derived from the runs (the study's statistics, correlations,
  increase, equations, design comparison, characteristic strengths, Sobol
  indices and the scorecard, the sampling check, the brick formats'
  scores, the design values of a study with a design target, the Sobol
  indices checked on the solver): row by row by their keys, every column,
  a number equal to DERIVED_RTOL relative (the tables are written to 4 or
  5 digits: a rerun that reproduces the runs reproduces their digits), a
  text exactly;
- the predictor (study/predictor.json): every value by its place in the
  file, numbers to DERIVED_RTOL, texts and flags exactly.

Each difference is named: the study, the table, the row, the column and
both values.  A table, or a whole study, that the reproduction lacks is
named as missing; a table named with --copied (copied in from the
committed results for its report, as `make reproduce` does with the
accuracy study's runs.csv; a path relative to the results folder) is
reported as not rerun and is no failure.  Only the tables named here are
compared: not the samples, the curves, the study's timing.csv, the
accuracy study's summaries and references, nor a design's rerun.csv
(made by tools/design_rerun.py, not by the workflow).

Exit status 0 when every expected table is there and as committed; 1 when
a run or a derived value differs, or a run, a table or a study is missing
(an empty reproduction fails), or the committed folder holds none of the
tables compared.
"""
import argparse
import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd

COMPARED = ["P_max_kN", "steps", "failure_mode", "status"]
# tables of single runs (relative to a study's folder), their run keys, what to call them
# (LEVEL: the study's swept level column, by the study's name: level_column)
LEVEL = "<level>"
TABLES = [
    ("study/runs.parquet", ["variant", LEVEL, "sample"], "study runs"),
    ("validation/summary.csv", ["run"], "validation runs"),
    ("stability/hard_cases.csv", ["run"], "hard cases"),
    ("reduced/summary.csv", ["case", "model"], "reduced-model runs"),
    ("specimens/summary.csv", ["case"], "specimen runs"),
    ("modelform/summary.csv", ["case", "sigma_v_mpa", "assumption", "option"], "model-form runs"),
    ("accuracy/runs.csv", ["case", "setting"], "accuracy runs"),
    ("sobol_check/runs.parquet", ["variant", LEVEL, "sample"], "Sobol check runs"),
]


# derived tables (relative to a study's folder), their row keys: the
# number of leading columns that name a row (the study's level column has
# the study's name), and what to call them
DERIVED = [
    ("study/statistics.csv", 3, "statistics"),
    ("study/correlations.csv", 3, "correlations"),
    ("study/increase.csv", 2, "increase of the mean"),
    ("study/equations.csv", 1, "prediction equations"),
    ("study/design_comparison.csv", 1, "design comparison"),
    ("study/characteristic.csv", 2, "characteristic strengths"),
    ("study/sensitivity.csv", 5, "Sobol indices"),
    ("study/paper_comparison.csv", 3, "scorecard against the source paper"),
    ("study/sampling_check.csv", 1, "sampling check"),
    ("studies/geometry_formats.csv", 1, "brick formats' scores"),
    ("design/design.csv", 1, "design values"),
    ("sobol_check/check.csv", 1, "Sobol indices checked on the solver"),
]
PREDICTOR = ("study/predictor.json", "predictor")
DERIVED_RTOL = 1e-9


def read(path):
    return pd.read_parquet(path) if path.suffix == ".parquet" else pd.read_csv(path)


def compare(committed, new, keys):
    """The committed and new rows side by side (outer join on the keys),
    with a column 'same': every compared value equal (NaN equals NaN)."""
    m = committed[keys + COMPARED].merge(new[keys + COMPARED], on=keys, how="outer",
                                         suffixes=("_committed", "_new"), indicator=True)
    same = m["_merge"] == "both"
    for c in COMPARED:
        a, b = m[f"{c}_committed"], m[f"{c}_new"]
        same &= (a == b) | (a.isna() & b.isna())
    return m.assign(same=same)


def _missing(v):
    return v is None or (isinstance(v, (float, np.floating)) and np.isnan(v))


def _number(v):
    return isinstance(v, (int, float, np.number)) and not isinstance(v, (bool, np.bool_))


def _equal(x, y):
    """Two values of a derived table or a predictor: numbers (not flags) to
    DERIVED_RTOL, a missing value (NaN, null) equal to a missing one,
    anything else exactly."""
    if _missing(x) or _missing(y):
        return _missing(x) and _missing(y)
    if _number(x) and _number(y):
        return bool(np.isclose(x, y, rtol=DERIVED_RTOL, atol=0.0))
    return x == y


def compare_derived(committed, new, n_keys):
    """Every difference between two versions of a derived table, as
    (row key, column, committed value, new value): rows matched by their
    first ``n_keys`` columns, numbers equal to DERIVED_RTOL, texts exactly;
    a row or a column only one side has is a difference too."""
    keys = list(committed.columns[:n_keys])
    a, b = committed.set_index(keys), new.set_index(keys) if set(keys) <= set(new.columns) else None
    if b is None:
        return [("(the table)", "columns", ", ".join(committed.columns), ", ".join(new.columns))]
    out = [(k, "(row)", "present" if k in a.index else "absent", "present" if k in b.index else "absent")
           for k in a.index.symmetric_difference(b.index)]
    out += [("(every row)", c, "present" if c in a else "absent", "present" if c in b else "absent")
            for c in a.columns.symmetric_difference(b.columns)]
    for key in a.index.intersection(b.index):
        for col in a.columns.intersection(b.columns):
            x, y = a.at[key, col], b.at[key, col]
            if not _equal(x, y):
                out.append((key, col, x, y))
    return out


def flatten(value, place=""):
    """A JSON document as {place: value}: a mapping's entries by their
    keys, a list's by their positions, joined with '/'."""
    if isinstance(value, dict):
        items = value.items()
    elif isinstance(value, list):
        items = enumerate(value)
    else:
        return {place: value}
    out = {}
    for k, v in items:
        out.update(flatten(v, f"{place}/{k}" if place else str(k)))
    return out or {place: value}


def compare_predictor(committed, new):
    """Every difference between two predictor files (parsed JSON), as
    (place, committed value, new value): a place only one side has is a
    difference too."""
    a, b = flatten(committed), flatten(new)
    return [(p, a.get(p, "(absent)"), b.get(p, "(absent)")) for p in sorted(a.keys() | b.keys())
            if p not in a or p not in b or not _equal(a[p], b[p])]


def _shown(x):
    return repr(x.item() if isinstance(x, np.generic) else x)


def studies(committed):
    """The committed studies: the folder itself and every folder below it
    holding study/runs.parquet, as paths relative to it ('.' the folder)."""
    below = {p.parent.parent for p in committed.rglob("study/runs.parquet")} - {committed}
    return [Path(".")] + sorted(p.relative_to(committed) for p in below)


def level_column(folder):
    """A study's swept level column, as its statistics table names it (its
    second column: variant, level, mode); sigma_v_mpa without one."""
    stats = folder / "study" / "statistics.csv"
    return pd.read_csv(stats, nrows=0).columns[1] if stats.is_file() else "sigma_v_mpa"


def expected(committed, study):
    """The tables a committed study holds: (kind, path relative to the
    study, its keys, its name), kind 'runs', 'derived' or 'predictor'."""
    level = level_column(committed / study)
    kinds = [("runs", t, [level if k == LEVEL else k for k in keys], name) for t, keys, name in TABLES]
    kinds += [("derived", t, n_keys, name) for t, n_keys, name in DERIVED]
    kinds += [("predictor", PREDICTOR[0], None, PREDICTOR[1])]
    return [k for k in kinds if (committed / study / k[1]).is_file()]


class Tally:
    """What a comparison found: runs and derived values that differ,
    tables missing, tables copied."""

    def __init__(self):
        self.runs, self.values, self.missing, self.copied, self.tables = 0, 0, [], [], 0

    @property
    def failed(self):
        return bool(self.runs or self.values or self.missing)


def _table(kind, table, old, new, keys, name, tally):
    """The lines of one table compared (both files present)."""
    if kind == "runs":
        m = compare(read(old), read(new), keys)
        bad = m[~m["same"]]
        tally.runs += len(bad)
        verdict = "identical" if bad.empty else f"identical; {len(bad)} differ or are missing"
        lines = [f"{name}: {int(m['same'].sum())} of {len(m)} {verdict} ({', '.join(COMPARED)})"]
        if not bad.empty:
            lines += ["    " + x for x in bad.drop(columns="same").head(30).to_string(index=False).splitlines()]
        return lines
    if kind == "derived":
        diff = compare_derived(pd.read_csv(old), pd.read_csv(new), keys)
        shown = [f"    {key}, {col}: committed {_shown(x)}, now {_shown(y)}" for key, col, x, y in diff[:30]]
    else:
        diff = compare_predictor(json.loads(old.read_text()), json.loads(new.read_text()))
        shown = [f"    {place}: committed {_shown(x)}, now {_shown(y)}" for place, x, y in diff[:30]]
    tally.values += len(diff)
    return [f"{name} ({table}): " + ("identical" if not diff else f"{len(diff)} values differ")] + shown


def _count(n, word, plural=None):
    return f"{n} {word if n == 1 else plural or word + 's'}"


def _study(args, study, tally):
    """The lines of one study compared: its verdict, then each table's.  A
    table that is missing, or cannot be read or compared (a column it
    lacks), counts as missing."""
    new_root = args.new / study
    before = (tally.runs, tally.values, len(tally.missing))
    lines, absent = [], []
    for kind, table, keys, name in expected(args.committed, study):
        path = (study / table).as_posix()
        if path in args.copied:
            tally.copied.append(path)
            lines.append(f"{name}: not rerun (copied from the committed results)")
            continue
        try:
            if not (new_root / table).is_file():
                raise FileNotFoundError(f"missing from {new_root}")
            lines += _table(kind, table, args.committed / path, args.new / path, keys, name, tally)
            tally.tables += 1
        except (OSError, KeyError, ValueError) as e:
            tally.missing.append(path)
            absent.append(table)
            lines.append(f"{name} ({table}): NOT reproduced: {e}")
    label = f"main study, {args.committed}" if study == Path(".") else f"study {args.committed / study}"
    if not new_root.is_dir():       # the whole study missing: its tables on one line
        lines = [x for x in lines if "NOT reproduced" not in x] + [f"missing: {', '.join(absent)}"]
        return [f"{label}: NOT reproduced: the whole study is missing (no folder {new_root})"] + ["  " + x for x in lines]
    failed = (tally.runs, tally.values, len(tally.missing)) != before
    verdict = f"NOT reproduced ({_count(len(absent), 'table')} missing)" if absent else \
        "NOT reproduced" if failed else "reproduced"
    return [f"{label}: {verdict}"] + ["  " + x for x in lines]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("committed", type=Path, help="the committed results folder (results)")
    ap.add_argument("new", type=Path, help="the reproduction's results folder")
    ap.add_argument("--copied", nargs="*", default=[], metavar="TABLE",
                    help="tables (e.g. accuracy/runs.csv) the reproduction copied rather than rerun")
    args = ap.parse_args(argv)
    tally, found = Tally(), studies(args.committed)
    if not any(expected(args.committed, s) for s in found):
        print(f"NOT REPRODUCED: {args.committed} holds none of the tables compared")
        return 1
    for study in found:
        print("\n".join(_study(args, study, tally)))
    counts = f"{tally.runs} runs and {tally.values} derived values differ"
    if tally.failed:
        missing = f"; {_count(len(tally.missing), 'table')} missing (named above)" if tally.missing else ""
        print(f"NOT REPRODUCED: {counts}{missing}")
        return 1
    copied = f" ({len(tally.copied)} copied, not rerun: {', '.join(tally.copied)})" if tally.copied else ""
    print(f"REPRODUCED: {_count(len(found), 'study', 'studies')}, {_count(tally.tables, 'table')} rerun, every run, "
          f"derived value and predictor as committed{copied}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
