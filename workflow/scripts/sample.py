"""The samples of the study's variants (Study.draw; their check:
sampling_check.py), each record with the scene settings it gives and the
setting of each variable (study/settings.py): a job applies them without
the study file.  The rule's params hold what decides them (the study's
draw key), never its levels."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import json  # noqa: E402

from masonrydem.pipeline import plan  # noqa: E402

study = plan.study(sm.config)
for variant, path in zip(sm.params.variants, sm.output.samples):
    drawn = study.draw(variant)
    with open(path, "w") as f:
        f.write(json.dumps(drawn.records()))
    print(f"{variant}: {len(drawn.table)} samples, {drawn.describe()}")
