"""The further specimens' table, figure and caption."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402
from masonrydem.analysis.validation import specimen_figure, specimen_table  # noqa: E402

cases = sm.params.cases
results = {c: pd.read_parquet(p).iloc[0] for c, p in zip(cases, sm.input.results)}
curves = {c: pd.read_parquet(p) for c, p in zip(cases, sm.input.curves)}
scenes = {c: build_scene(cases[c]["scene"], cases[c]["overrides"]) for c in cases}
table = specimen_table(results, curves, scenes)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
specimen_figure(table, curves, sm.output.figure)
captions.write_caption(sm.input.template, sm.output.caption, **captions.specimens(table))
