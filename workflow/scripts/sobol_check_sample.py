"""The Sobol check's points (study.copula.pick_freeze; the check:
analysis/sobol_check.py) as a samples file of the study's form: each
record the sample's number in SALib's order, its values, its scene
settings and each variable's setting (study/settings.py).  Its code is the
sampling's alone, nothing of the analysis or the solver."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import json  # noqa: E402

from masonrydem.study.copula import pick_freeze  # noqa: E402
from masonrydem.study.sampling import Variable  # noqa: E402
from masonrydem.study.settings import record  # noqa: E402

design = sm.params.design
variables = tuple(Variable(**{**v, "bounds": tuple(v["bounds"]) if v["bounds"] else None})
                  for v in design["variables"])
correlations = {(a, b): rho for a, b, rho in design["correlations"]}
_, x = pick_freeze(variables, correlations, sm.params.check["base"], sm.params.check["seed"])
points = [{"sample": k, **{v.name: float(x[k, j]) for j, v in enumerate(variables)}} for k in range(len(x))]
with open(sm.output.samples, "w") as f:
    f.write(json.dumps([record(p, "wallette", variables, design["rules"]) for p in points]))
print(f"{len(points)} points: {sm.params.check['base']} base points x ({len(variables)} inputs + 2)")
