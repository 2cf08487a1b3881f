"""Run by run, a reproduction's results against the committed ones: the
step of `make reproduce` that says whether it reproduced them.

    python tools/compare_results.py results reproduction/results

For each table of single runs (the study's runs.parquet, the validation,
hard cases, reduced models, specimens, model-form and accuracy tables) it
matches the runs by their keys and compares P_max, the step count, the
failure mode and the status, exactly, at the precision the table is
written with (full for runs.parquet, the CSV's digits for the others).
Wall times are not compared.

Then each table derived from the runs (the study's statistics,
correlations, increase, equations, design comparison, characteristic
strengths, Sobol indices and the scorecard, the sampling check, the brick
formats' scores), row by row by its keys, every column: a number equal to
DERIVED_RTOL relative (the tables are written to 4 or 5 digits: a rerun
that reproduces the runs reproduces their digits), a text exactly.  Each
difference is named: the table, the row, the column and both values.

A table the reproduction does not have, or one named with --copied (copied
in from the committed results for its report, as `make reproduce` does
with the accuracy study's), is reported as not rerun.  Exit status 1 when
a run or a derived value differs or is missing.
"""
import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

COMPARED = ["P_max_kN", "steps", "failure_mode", "status"]
# table (relative to the results folder), its run keys, what to call it
TABLES = [
    ("study/runs.parquet", ["variant", "sigma_v_mpa", "sample"], "study runs"),
    ("validation/summary.csv", ["run"], "validation runs"),
    ("stability/hard_cases.csv", ["run"], "hard cases"),
    ("reduced/summary.csv", ["case", "model"], "reduced-model runs"),
    ("specimens/summary.csv", ["case"], "specimen runs"),
    ("modelform/summary.csv", ["case", "sigma_v_mpa", "assumption", "option"], "model-form runs"),
    ("accuracy/runs.csv", ["case", "setting"], "accuracy runs"),
]


# derived tables (relative to the results folder), their row keys: the
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
]
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
            if pd.isna(x) and pd.isna(y):
                continue
            numbers = isinstance(x, (int, float, np.number)) and isinstance(y, (int, float, np.number))
            same = np.isclose(x, y, rtol=DERIVED_RTOL, atol=0.0) if numbers else x == y
            if not same:
                out.append((key, col, x, y))
    return out


def _shown(x):
    return repr(x.item() if isinstance(x, np.generic) else x)


def _derived(args):
    """The derived tables compared: (lines to print, differences)."""
    lines, differ = [], 0
    for table, n_keys, name in DERIVED:
        if not (args.committed / table).is_file():
            continue
        if not (args.new / table).is_file() or table in args.copied:
            why = "copied from the committed results" if table in args.copied else f"{table} is not in {args.new}"
            lines.append(f"{name}: not rerun ({why})")
            continue
        diff = compare_derived(pd.read_csv(args.committed / table), pd.read_csv(args.new / table), n_keys)
        differ += len(diff)
        lines.append(f"{name} ({table}): " + ("identical" if not diff else f"{len(diff)} values differ"))
        lines += [f"    {key}, {col}: committed {_shown(x)}, now {_shown(y)}" for key, col, x, y in diff[:30]]
    return lines, differ


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("committed", type=Path, help="the committed results folder (results)")
    ap.add_argument("new", type=Path, help="the reproduction's results folder")
    ap.add_argument("--copied", nargs="*", default=[], metavar="TABLE",
                    help="tables (e.g. accuracy/runs.csv) the reproduction copied rather than rerun")
    args = ap.parse_args(argv)
    differ = 0
    for table, keys, name in TABLES:
        if not (args.new / table).is_file() or table in args.copied:
            why = "copied from the committed results" if table in args.copied else f"{table} is not in {args.new}"
            print(f"{name}: not rerun ({why})")
            continue
        m = compare(read(args.committed / table), read(args.new / table), keys)
        bad = m[~m["same"]]
        differ += len(bad)
        verdict = "identical" if bad.empty else f"identical; {len(bad)} differ or are missing"
        print(f"{name}: {int(m['same'].sum())} of {len(m)} {verdict} ({', '.join(COMPARED)})")
        if not bad.empty:
            print(bad.drop(columns="same").head(30).to_string(index=False))
    lines, derived = _derived(args)
    print("\n".join(lines))
    if differ or derived:
        print(f"NOT REPRODUCED: {differ} runs and {derived} derived values differ")
    else:
        print("REPRODUCED: every rerun run and every derived table as committed")
    return 1 if differ or derived else 0


if __name__ == "__main__":
    sys.exit(main())
