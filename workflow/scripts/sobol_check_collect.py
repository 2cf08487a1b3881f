"""The Sobol check's runs in one table (each run's lower-bound strength, as
the study's collect gives it) and the cost of their batches."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis.statistics import lower_bounds  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402
from masonrydem.specimen.protocol import DROP_WINDOW  # noqa: E402
from masonrydem.specimen.row import atomic_write, read_json  # noqa: E402

study = plan.study(sm.config)
runs = lower_bounds(pd.DataFrame([read_json(p) for p in sm.input.results]).sort_values("sample", ignore_index=True),
                    build_scene(study.scene).loading.drive.rate, DROP_WINDOW)
atomic_write(sm.output.runs, lambda p: runs.to_parquet(p, index=False))
seconds = [float(pd.read_csv(b, sep="\t")["s"].iloc[0]) for b in sm.input.benchmarks]
pd.DataFrame([dict(runs=len(runs), base=sm.params.base, batches=len(seconds),
                   batch_core_s=round(sum(seconds), 1))]).to_csv(sm.output.timing, index=False)
print(f"{len(runs)} runs, {len(seconds)} batches, {sum(seconds):.1f} s of one core")
