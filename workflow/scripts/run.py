"""One run of the scene with overrides (validation and accuracy runs): its
row, its curve and, when the rule asks for it, its final state."""
import sys

import numba

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)            # one thread per job
sys.stderr = sys.stdout = open(sm.log[0], "w")

from pathlib import Path  # noqa: E402

from masonrydem.runner import run_scene, write_outputs  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402

scene = load_scene(sm.input.scene, sm.params.overrides)
scene["name"] = ":".join([scene["name"], *sm.wildcards])
row, curve, specimen, solver = run_scene(scene, progress=True)
write_outputs(Path(sm.output.result).parent, row, curve, specimen, solver, state="state" in sm.output.keys())
print(row)
