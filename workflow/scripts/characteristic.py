"""Characteristic (5 %) strengths of the study, per variant and level."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.analysis import fractiles  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
level, _ = of_study(sm.params.analysis)
table = fractiles.with_design(fractiles.characteristic_table(runs, level), pd.read_csv(sm.input.design), level)
table.to_csv(sm.output.table, index=False, float_format="%.4g")
print(table.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **fractiles.caption_values(table, level))
