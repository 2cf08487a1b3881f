"""The hard-cases table and its caption."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.analysis.validation import hard_cases_table  # noqa: E402
from masonrydem.dem import PEAK_UNBALANCE  # noqa: E402

results = {r: pd.read_parquet(p).iloc[0] for r, p in zip(sm.params.runs, sm.input.results)}
table = hard_cases_table(results, sm.params.expect)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.hard_cases(table, PEAK_UNBALANCE))
