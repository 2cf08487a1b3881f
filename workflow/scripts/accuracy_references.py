"""The accuracy study's references: the refinement paths' runs and those
varied around a path level, one row each, with the solver that made them
(results/accuracy/references.csv; the summary reads them from there)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis.accuracy import RUN_COLUMNS  # noqa: E402

rows = [dict(case=case, setting=setting, **pd.read_parquet(p).iloc[0][RUN_COLUMNS + ["solver_version"]].to_dict())
        for (case, setting), p in zip(sm.params.runs, sm.input.results)]
table = pd.DataFrame(rows)
table.to_csv(sm.output.table, index=False, float_format="%.17g")
print(table.to_string())
