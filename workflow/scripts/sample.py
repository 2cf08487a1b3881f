"""Latin Hypercube samples of the study's variants (their check:
sampling_check.py), each record with the scene settings it gives and the
setting of each variable (study/settings.py): a job applies them without
the study file.  Everything it reads is in the rule's params (the study's
design, its wallette's units and joints), so that its code is the
sampling's alone, nothing of the solver."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import json  # noqa: E402

import numpy as np  # noqa: E402

from masonrydem.study.sampling import Variable, field_samples, records, study_samples  # noqa: E402
from masonrydem.study.settings import record  # noqa: E402

design = sm.params.design
variables = tuple(Variable(**{**v, "bounds": tuple(v["bounds"]) if v["bounds"] else None})
                  for v in design["variables"])
correlations = {(a, b): rho for a, b, rho in design["correlations"]}
centres = {what: np.array(xy, float).reshape(-1, 2) for what, xy in design["items"].items()}
wallettes, items, _ = study_samples(design["samples"], design["seed"], len(centres["unit"]), len(centres["joint"]),
                                    variables, correlations)
for variant, path in zip(sm.params.variants, sm.output.samples):
    draw, length = design["variants"][variant]["draw"], design["variants"][variant]["correlation_length"]
    table = {"wallette": wallettes, "items": items}.get(draw)
    if draw == "field":
        table = field_samples(design["samples"], design["seed"], variables, correlations, centres, length)
    text = json.dumps([record(r, draw, variables, design["rules"]) for r in records(table)])
    with open(path, "w") as f:
        f.write(text)
    how = {"wallette": "one draw per wallette", "items": "one draw per unit and joint",
           "field": f"random fields, correlation length {length} m"}[draw]
    print(f"{variant}: {len(table)} samples, {how}")
