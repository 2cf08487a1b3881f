"""Both bending directions of one study on the same samples: the pairs of
this workflow's runs and the other direction's (config directions.pair),
f_x1 and f_x2 per level with their intervals, mu with Fieller's interval,
and EN 1996-1-1 and AS 3700 beside them (analysis/directions.py)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import directions as D  # noqa: E402
from masonrydem.analysis import labsheet  # noqa: E402
from masonrydem.analysis import validation as V  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.report import captions, tables  # noqa: E402
from masonrydem.report import directions as RD  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402

cfg, study = sm.params.directions, plan.study(sm.config)
level, _ = of_study(sm.params.analysis)
own = pd.read_parquet(sm.input.runs)
other = pd.read_parquet(sm.input.pair)
horizontal, vertical = (own, other) if study.direction == "horizontal" else (other, own)
pairs = D.paired(horizontal, vertical, level.column)
mean = V.design_inputs(build_scene(study.scene, settings=study.mean_settings()))
table = D.with_codes(D.directions_table(pairs, level.column), pairs, level.column, mean["ft_joints"],
                     mean["ft_units"], cfg["mortar"])
table.to_csv(sm.output.table, index=False, float_format="%.6g")
print(table.to_string())
tested = pd.DataFrame()
words = "No wallette tests of the user's were given (config directions.wallettes)."
if sm.input.wallettes:
    sheet = labsheet.read_sheet(sm.input.wallettes[0])
    variant = study.regression_variant
    ok = {d: r[r.ok & (r.variant == variant)] for d, r in (("horizontal", horizontal), ("vertical", vertical))}
    tested = D.placed(sheet, ok, level.column)
    words = RD.tests_words(tested, D.agreement(tested, level.column), sheet["name"], variant, level)
tested.to_csv(sm.output.tests, index=False, float_format="%.6g")
print(tested.to_string())
RD.figure(table, level, sm.output.figure, tested)
title = "Both bending directions on the same samples: f_x1, f_x2 and mu per level, the codes beside them"
open(sm.output.page, "w").write(tables.html_table(table, title))
captions.write_caption(sm.input.template, sm.output.caption,
                       tests=words,
                       **RD.caption(table, level, cfg["mortar"], mean, len(own), len(other), study.name))
