"""Deterministic validation: table, load-displacement figure and caption."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.analysis.validation import figure, summary_table  # noqa: E402

results = {r: pd.read_parquet(p).iloc[0] for r, p in zip(sm.params.runs, sm.input.results)}
curves = {r: pd.read_parquet(p) for r, p in zip(sm.params.runs, sm.input.curves)}
table = summary_table(results, curves)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
figure(table, curves, sm.output.figure)
captions.write_caption(sm.input.template, sm.output.caption, **captions.validation_summary(table))
