"""The reduced models' table and its caption."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.analysis.validation import reduced_table  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402

scenes = {tuple(run): build_scene(sm.input.scene, overrides) for run, overrides in zip(sm.params.runs,
                                                                                     sm.params.overrides)}
table = reduced_table({tuple(run): pd.read_parquet(p).iloc[0] for run, p in zip(sm.params.runs, sm.input.results)},
                      sm.params.tolerance, scenes)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.reduced(table, sm.params.tolerance))
