"""One simulation of the study: its row and curve, whatever its status.  A
run that raises (a scene the sample makes invalid, say) is recorded too:
status 'error', the exception as its message, the sample's inputs, an empty
curve."""
import sys
import traceback

import numba

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)            # one thread per job: no oversubscription
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.runner import atomic_write  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402
from masonrydem.sampling import sample_inputs  # noqa: E402
from masonrydem.study import run_sample  # noqa: E402

variant, sv, sample = sm.wildcards.variant, float(sm.wildcards.sv), int(sm.wildcards.sample)
samples = pd.read_parquet(sm.input.samples)
try:
    row, curve, _, _ = run_sample(load_scene(sm.input.scene, sm.params.overrides), samples, variant, sv, sample)
except Exception as e:  # nothing lost: the row says what happened
    traceback.print_exc()
    row = dict(variant=variant, sample=sample, sigma_v_mpa=sv, status="error", ok=False,
               message=f"{type(e).__name__}: {e}", **sample_inputs(samples[samples["sample"] == sample].iloc[0]))
    curve = pd.DataFrame({"step": pd.Series(dtype="int64"), "displacement_mm": pd.Series(dtype="float64"),
                          "load_kN": pd.Series(dtype="float64"), "ratio": pd.Series(dtype="float64"),
                          "unbalance": pd.Series(dtype="float64")}).assign(
        variant=variant, sample=sample, sigma_v_mpa=sv)
atomic_write(sm.output.curve, lambda p: curve.to_parquet(p, index=False))
atomic_write(sm.output.result, lambda p: pd.DataFrame([row]).to_parquet(p, index=False))
print(row)
