"""The study's Sobol indices against direct pick-freeze estimates from the
check's runs (analysis/sobol_check.py)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import sobol_check as C  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.report import captions  # noqa: E402

check, spec = sm.params.check, sm.params.analysis
level, _ = of_study(spec)
study = plan.study(sm.config)
columns = [spec["columns"][v.name] for v in study.variables]
runs = pd.read_parquet(sm.input.runs)
timing = pd.read_csv(sm.input.timing).iloc[0]
direct = C.direct_indices(runs.strength_mpa, runs.ok, len(columns), check["resamples"], check["seed"])
s = pd.read_csv(sm.input.sensitivity)
rows = s[(s.variant == check["variant"]) & (s[level.column] == float(check["level"])) & (s["mode"] == "all")]
table = C.check_table(direct, rows.set_index("input"), columns)
table.to_csv(sm.output.table, index=False, float_format="%.4g")
print(table.to_string())
captions.write_caption(sm.input.template, sm.output.caption,
                       **C.caption_values(table, direct, runs, check, level, rows, int(timing.batches),
                                          float(timing.batch_core_s)))
