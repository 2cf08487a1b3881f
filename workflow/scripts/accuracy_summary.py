"""The accuracy sweep: errors against the converged reference, Pareto
fronts and the knee."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem import accuracy, captions  # noqa: E402

COLUMNS = ["P_max_kN", "failure_mode", "ok", "status", "steps", "wall_time_s", "blocks", "cells", "subcontact_refine",
           "tets", "subcontacts", "units"]
rows = [dict(case=case, setting=setting, **pd.read_parquet(p).iloc[0][COLUMNS].to_dict())
        for (case, setting), p in zip(sm.params.runs, sm.input.results)]
tolerance = sm.params.tolerance
table, conv = accuracy.sweep_table(rows, sm.params.cases, sm.params.path, sm.params.candidates,
                                   sm.params.path_tolerance)
choice = accuracy.choose(table, conv, tolerance)
table.to_csv(sm.output.runs, index=False, float_format="%.6g")
conv.to_csv(sm.output.convergence, index=False, float_format="%.6g")
choice.to_csv(sm.output.choice, index=False, float_format="%.6g")
print(conv.to_string())
print(choice.to_string())
print("defaults (config numerics):", sm.params.numerics)
captions.write_caption(sm.input.templates[0], sm.output.captions[0], **captions.accuracy_convergence(conv))
captions.write_caption(sm.input.templates[1], sm.output.captions[1], **captions.accuracy_choice(
    table, conv, choice, sm.params.baselines, tolerance, sm.params.numerics))
