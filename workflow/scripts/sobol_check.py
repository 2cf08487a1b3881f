"""The study's Sobol indices against direct pick-freeze estimates from the
check's runs (analysis/sobol_check.py)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import sobol_check as C  # noqa: E402
from masonrydem.analysis.statistics import lower_bounds, of_study  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.report import captions  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402
from masonrydem.specimen.protocol import DROP_WINDOW  # noqa: E402
from masonrydem.specimen.row import atomic_write, read_json  # noqa: E402

check, spec = sm.params.check, sm.params.analysis
level, _ = of_study(spec)
study = plan.study(sm.config)
columns = [spec["columns"][v.name] for v in study.variables]
runs = lower_bounds(pd.DataFrame([read_json(p) for p in sm.input.results]).sort_values("sample", ignore_index=True),
                    build_scene(study.scene).loading.drive.rate, DROP_WINDOW)
atomic_write(sm.output.runs, lambda p: runs.to_parquet(p, index=False))
direct = C.direct_indices(runs.strength_mpa, runs.ok, len(columns), check["resamples"], check["seed"])
s = pd.read_csv(sm.input.sensitivity)
rows = s[(s.variant == check["variant"]) & (s[level.column] == float(check["level"])) & (s["mode"] == "all")]
table = C.check_table(direct, rows.set_index("input"), columns)
table.to_csv(sm.output.table, index=False, float_format="%.4g")
print(table.to_string())
seconds = [float(pd.read_csv(b, sep="\t")["s"].iloc[0]) for b in sm.input.benchmarks]
pd.DataFrame([dict(runs=len(runs), base=check["base"], rows_kept=direct["rows"], rows_left_out=direct["left_out"],
                   batches=len(seconds), batch_core_s=round(sum(seconds), 1))]).to_csv(sm.output.timing, index=False)
captions.write_caption(sm.input.template, sm.output.caption,
                       **C.caption_values(table, direct, runs, check, level, rows, seconds))
