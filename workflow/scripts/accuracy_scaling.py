"""How run time grows with the number of units and with cells per edge."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import accuracy  # noqa: E402
from masonrydem.report import captions  # noqa: E402

units = pd.concat([pd.read_parquet(p) for p in sm.input.scaling], ignore_index=True).assign(courses=sm.params.courses)
table = accuracy.scaling(units, pd.read_csv(sm.input.runs), sm.params.settings)
table.to_csv(sm.output.table, index=False, float_format="%.6g")
print(table.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.accuracy_scaling(table, sm.params.courses))
