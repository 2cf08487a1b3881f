"""The accuracy sweep: errors against the converged reference, Pareto
fronts and the knee."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import accuracy  # noqa: E402
from masonrydem.report import captions  # noqa: E402


def rows_of(runs, results):
    return [dict(case=case, setting=setting, **pd.read_parquet(p).iloc[0][accuracy.RUN_COLUMNS].to_dict())
            for (case, setting), p in zip(runs, results)]


# the references from their table, once the coarsest path level rerun now
# has shown that they are today's solver's
references = pd.read_csv(sm.input.references)
accuracy.check_references(references, rows_of(sm.params.checks, sm.input.checks))
kept = {(r["case"], r["setting"]): r for r in references[["case", "setting", *accuracy.RUN_COLUMNS]].to_dict("records")}
missing = [run for run in map(tuple, sm.params.references) if run not in kept]
if missing:
    raise ValueError(f"results/accuracy/references.csv lacks the reference runs {missing}: run them "
                     "(snakemake --cores 2 --forcerun accuracy_references accuracy)")
rows = rows_of(sm.params.runs, sm.input.results) + [kept[tuple(run)] for run in sm.params.references]
order = {run: i for i, run in enumerate(sm.params.all_runs)}
rows.sort(key=lambda r: order[(r["case"], r["setting"])])
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
# the paths' tolerance (config accuracy.path_tolerance): a path has converged when its two finest levels lie within it
captions.write_caption(sm.input.templates[0], sm.output.captions[0], tolerance=f"{100 * sm.params.path_tolerance:g} %",
                       **captions.accuracy_convergence(conv))
captions.write_caption(sm.input.templates[1], sm.output.captions[1], **captions.accuracy_choice(
    table, conv, choice, sm.params.baselines, tolerance, sm.params.numerics))
