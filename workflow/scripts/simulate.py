"""One simulation of the study: its row and curve, whatever its status."""
import sys

import numba

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)            # one thread per job: no oversubscription
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.runner import atomic_write, run_scene  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402
from masonrydem.study import study_scene  # noqa: E402

variant, sv, i = sm.wildcards.variant, float(sm.wildcards.sv), int(sm.wildcards.sample)
samples = pd.read_parquet(sm.input.samples)
sample = samples[samples["sample"] == i].iloc[0]
scene = study_scene(load_scene(sm.input.scene, sm.params.overrides), variant, sample, sv * 1e6)
row, curve, _, _ = run_scene(scene, progress=True)
ids = dict(variant=variant, sample=i)
row = {**ids, **row, "sigma_v_mpa": sv}
atomic_write(sm.output.curve, lambda p: curve.assign(**ids, sigma_v_mpa=sv).to_parquet(p, index=False))
atomic_write(sm.output.result, lambda p: pd.DataFrame([row]).to_parquet(p, index=False))
print(row)
