"""The geometry study's equations on brick formats they were not fitted to."""
import json
import sys
from pathlib import Path

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions, tables  # noqa: E402
from masonrydem.analysis import brick_formats as formats  # noqa: E402

predictor = json.loads(Path(sm.input.predictor).read_text())
own = json.loads(Path(sm.input.own).read_text())     # this workflow's study: the fixed-geometry equations
held = {}
for (name, spec), runs in zip(sm.params.formats.items(), sm.input.runs):
    geometry, variant = formats.format_of(spec["study"])
    held[name] = (pd.read_parquet(runs), geometry, variant, None if spec.get("results") else own)
table = formats.held_out_table(predictor, held, pd.read_parquet(sm.input.fitted))
table.to_csv(sm.output.table, index=False, float_format="%.4g")
Path(sm.output.page).write_text(tables.html_table(table, "The geometry study's equations on held-out formats"))
print(table.to_string())
eqs = pd.read_csv(sm.input.equations)
lines = [f"{r['mode']} failure: {r['equation']}" for _, r in eqs.iterrows() if pd.notna(r.get("alpha"))]
captions.write_caption(sm.input.template, sm.output.caption, **formats.caption_values(table, lines))
