"""Prediction equations (Lasso, 5-fold CV) per failure mode on the runs of
the study's regression variant; the lower-of-two prediction checked run
by run and against the design rules."""
import json
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from masonrydem.analysis import equations as E  # noqa: E402
from masonrydem.analysis import predict  # noqa: E402
from masonrydem.analysis import validation as V  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.report import captions  # noqa: E402
from masonrydem.report import figures as F  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402

reg = sm.params.analysis          # the study file's terms, the inputs' columns, the sweep (plan.analysis)
terms, columns, level, variant = tuple(reg["terms"]), reg["columns"], reg["level_column"], reg["regression_variant"]
runs = pd.read_parquet(sm.input.runs)
ns = runs[runs.ok & (runs.variant == variant)]
fits, rows, resid_sd = E.prediction_equations(ns, terms, columns)
# the equations' 95 % intervals: every resample refits both modes
intervals = E.equation_intervals(ns, terms, columns, **sm.params.bootstrap, jobs=sm.threads,
                                 progress=lambda k, n: print(f"bootstrap: {k} of {n} resamples", flush=True))
pd.DataFrame(rows).merge(intervals, on="mode", how="left").to_csv(sm.output.equations, index=False,
                                                                  float_format="%.5g")
F.predicted_vs_simulated(fits, sm.output.predicted)
scene = build_scene(sm.input.scene)
with open(sm.output.predictor, "w") as f:       # masonrydem predict
    skipped = {r["mode"]: r["equation"] for r in rows if r["mode"] in ("joint", "brick") and r["mode"] not in fits}
    json.dump(predict.build(fits, ns, scene, f"its {len(ns)} ok {variant} runs", columns, reg["units"], variant,
                            sm.params.settings,
                            study=reg["study"], level=reg["level"], skipped=skipped,
                            labs=predict.lab_conversions(plan.study(sm.config).provenance)), f, indent=1)
print(pd.DataFrame(rows).to_string())
captions.write_captions(sm.input.templates[:1], sm.output.captions[:1],
                        dict(equations=captions.equations(rows, terms, variant)))
if reg["precompression"]:
    study = plan.study(sm.config)
    design = V.design_inputs(build_scene(study.scene, settings=study.mean_settings()))
    table = V.design_table(fits, ns, resid_sd, np.linspace(runs[level].min(), runs[level].max(), 51), design,
                           reg["means"], columns, reg["level"], level, scene.loading.bending.direction)
    simulated = ns.groupby(level).strength_mpa.agg(["mean", "std"])
    F.design_comparison(table, simulated, sm.output.design, variant, of_study(reg)[0], list(fits))
    table.to_csv(sm.output.design_table, index=False, float_format="%.5g")
    captions.write_captions(sm.input.templates[1:], sm.output.captions[1:], dict(
        design_comparison=captions.design_comparison(table, simulated, list(fits), resid_sd, runs["sample"].nunique(),
                                                     design, variant)))
else:   # the design rules are functions of the precompression at the mean properties
    why = (f"No design comparison: the design rules (Lourenco-Gaetani, AS3700) are functions of the "
           f"precompression, and this study sweeps {reg['setting']} ({reg['level']}).")
    F.placeholder(why, sm.output.design)
    pd.DataFrame(dict(note=[why])).to_csv(sm.output.design_table, index=False)
    with open(sm.output.captions[1], "w") as f:
        f.write(why + "\n")
