"""The model-form study's summary and its caption."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.analysis.validation import modelform_table  # noqa: E402

results = {tuple(run): pd.read_parquet(p).iloc[0] for run, p in zip(sm.params.runs, sm.input.results)}
table = modelform_table(results, sm.params.labels)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.modelform(table))
