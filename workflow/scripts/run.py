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

from masonrydem.runner import run_and_write  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402

scene = load_scene(sm.input.scene, sm.params.overrides)
scene["name"] = ":".join([scene["name"], *sm.wildcards])
state = "state" in sm.output.keys()
row, error = run_and_write(Path(sm.output.result).parent, scene, progress=True, state=state)
if error is not None and state:   # an empty final state: the run left none
    import pyvista as pv
    pv.MultiBlock().save(sm.output.state)
print(row)
