"""Run by run, a reproduction's results against the committed ones: the
step of `make reproduce` that says whether it reproduced them.

    python tools/compare_results.py results reproduction/results

For each table of single runs (the study's runs.parquet, the validation,
hard cases, reduced models, specimens, model-form and accuracy tables) it
matches the runs by their keys and compares P_max, the step count, the
failure mode and the status, exactly, at the precision the table is
written with (full for runs.parquet, the CSV's digits for the others).
Wall times are not compared.  A table the reproduction does not have, or
one named with --copied (copied in from the committed results for its
report, as `make reproduce` does with the accuracy study's), is reported as
not rerun.  Exit status 1 when a run differs or is missing.
"""
import argparse
import sys
from pathlib import Path

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
    print("REPRODUCED: every rerun run as committed" if not differ else f"NOT REPRODUCED: {differ} runs differ")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
