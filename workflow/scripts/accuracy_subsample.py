"""The study's conclusions on a subsample: default against fine settings."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import accuracy  # noqa: E402
from masonrydem.report import captions, figures  # noqa: E402
from masonrydem.specimen.row import read_json  # noqa: E402

default = pd.DataFrame([read_json(p) for p in sm.input.default])
fine = pd.DataFrame([read_json(p) for p in sm.input.fine])
table = accuracy.compare_subsample(default, fine)
table.to_csv(sm.output.table, index=False, float_format="%.6g")
print(table.T.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.accuracy_subsample(table, sm.params.fine))
figures.accuracy_subsample(accuracy.paired(default, fine), sm.output.figure)
