"""The Sobol check's points (Study.pick_freeze; the check:
analysis/sobol_check.py) as a samples file of the study's form: each
record the sample's number in SALib's order, its values, its scene
settings and each variable's setting (study/settings.py)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import json  # noqa: E402

from masonrydem.pipeline import plan  # noqa: E402

study = plan.study(sm.config)
points = study.pick_freeze(sm.params.check["base"], sm.params.check["seed"])
with open(sm.output.samples, "w") as f:
    f.write(json.dumps(points))
print(f"{len(points)} points: {sm.params.check['base']} base points x ({len(study.variables)} inputs + 2)")
