"""One simulation of the study: its row and curve, whatever its status."""
import sys

import numba

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)            # one thread per job: no oversubscription
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.runner import atomic_write  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402
from masonrydem.study import run_sample  # noqa: E402

row, curve, _, _ = run_sample(load_scene(sm.input.scene, sm.params.overrides), pd.read_parquet(sm.input.samples),
                              sm.wildcards.variant, float(sm.wildcards.sv), int(sm.wildcards.sample))
atomic_write(sm.output.curve, lambda p: curve.to_parquet(p, index=False))
atomic_write(sm.output.result, lambda p: pd.DataFrame([row]).to_parquet(p, index=False))
print(row)
