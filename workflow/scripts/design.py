"""The wallette's characteristic flexural strength per level from a study
whose inputs were fitted to a lab's results, with the lab's uncertainty
carried by re-weighting the study's runs, beside EN 1996-1-1's f_xk2 and
AS 3700 (src/masonrydem/analysis/design.py)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import design  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.report import captions, tables  # noqa: E402

cfg, study = sm.params.design, plan.study(sm.config)
level, _ = of_study(sm.params.analysis)
runs = pd.read_parquet(sm.input.runs)
runs = runs[runs.variant == study.regression_variant]
lab, sampling, columns, as3700 = design.study_inputs(study, cfg.get("bond"), cfg.get("units"))
direction = study.direction
table = design.design_table(runs, level.column, columns, sampling, lab, cfg["gamma_M"],
                            design.FXK2_CLAY[cfg["fxk2"]], as3700, cfg["seed"], cfg["draws"], direction,
                            design.FXK1_CLAY[cfg["fxk2"]])
table.to_csv(sm.output.table, index=False, float_format="%.4g")
print(table.to_string())
lines = design.caption_lines(table, level.column, level.unit)
print("\n".join(lines))
title = "The wallette's characteristic flexural strength from the lab's results, per level"
open(sm.output.page, "w").write(tables.html_table(table, title))
captions.write_caption(sm.input.template, sm.output.caption, lines="\n".join(f"- {x}" for x in lines),
                       variant=study.regression_variant, en=design.en_words(direction, cfg["fxk2"]),
                       gamma_M=f"{cfg['gamma_M']:g}", draws=cfg["draws"],
                       as3700=design.as3700_words(as3700, cfg.get("bond"), cfg.get("units"), direction),
                       lab=design.lab_words(study))
