"""One run of the scene with overrides (validation and accuracy runs): its
row, its curve and, when the rule asks for it, its final state.  A run
that raises still writes its row (status 'error', the exception as its
message) and an empty curve: nothing is lost, and the summaries say which
run failed and why."""
import sys

import numba

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)            # one thread per job
sys.stderr = sys.stdout = open(sm.log[0], "w")

from pathlib import Path  # noqa: E402

import time  # noqa: E402
import traceback  # noqa: E402

from masonrydem.runner import record_error, run_scene, write_outputs  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402

scene = load_scene(sm.input.scene, sm.params.overrides)
scene["name"] = ":".join([scene["name"], *sm.wildcards])
out = Path(sm.output.result).parent
t0 = time.perf_counter()
try:
    row, curve, specimen, solver = run_scene(scene, progress=True)
except Exception as e:  # nothing lost: the row says what happened
    traceback.print_exc()
    row = record_error(out, scene, e, time.perf_counter() - t0)
    if "state" in sm.output.keys():   # an empty final state: the run left none
        import pyvista as pv
        pv.MultiBlock().save(sm.output.state)
else:
    write_outputs(out, row, curve, specimen, solver, state="state" in sm.output.keys())
print(row)
