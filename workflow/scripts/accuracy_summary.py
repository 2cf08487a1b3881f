"""The accuracy sweep: errors against the converged reference, Pareto
fronts and the knee."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem import accuracy, figures  # noqa: E402

A = sm.params.accuracy
COLUMNS = ["P_max_kN", "failure_mode", "ok", "status", "steps", "wall_time_s", "cells", "subcontact_refine",
           "tets", "subcontacts", "units"]
rows = []
for path in sm.input.results:
    case, setting = path.split("/")[-3:-1]
    r = pd.read_parquet(path).iloc[0]
    rows.append(dict(case=case, setting=setting, **r[COLUMNS].to_dict()))
table, conv = accuracy.sweep_table(rows, [c["name"] for c in A["cases"]], sm.params.path,
                                   band=A["tolerance"] / 2)
# a case without a converged reference cannot judge a setting
judged = conv.loc[~conv.method.str.startswith("NOT CONVERGED"), "case"]
judge = table[table.case.isin(judged)]
# the knee among the mesh settings; the defaults beside them
choice = accuracy.knee(judge[judge.grid], A["tolerance"])
default = accuracy.knee(judge[judge.setting == "default"], A["tolerance"]).assign(knee=False)
choice = pd.concat([choice, default], ignore_index=True).sort_values("total_time_s", kind="stable")
choice["default"] = choice.setting == "default"
table.to_csv(sm.output.runs, index=False, float_format="%.6g")
conv.to_csv(sm.output.convergence, index=False, float_format="%.6g")
choice.to_csv(sm.output.choice, index=False, float_format="%.6g")
print(conv.to_string())
print(choice.to_string())
print("defaults (config numerics):", sm.params.numerics)


def describe(setting):
    if not (choice.setting == setting).any():
        return f"**{setting}**, not judged (no case has a converged reference)"
    r = choice[choice.setting == setting].iloc[0]
    return (f"**{setting}**, largest error {100 * r.max_abs_error:.2f} %, modes "
            f"{'right' if r.modes_ok else 'WRONG'}, {r.total_time_s:.1f} s")


knee = choice.loc[choice.knee, "setting"]
lines = [f"- {r.case}: **{r.reference_kN:.3f} kN** ({r.reference_mode} failure), {r.method}; path "
         f"(setting: P_max kN) {r.levels}; finest level {100 * r.finest_error:+.2f} % from the reference"
         for r in conv.itertuples()]
figures.write_caption(sm.input.templates[0], sm.output.captions[0], lines="\n".join(lines))
# one setting at a time: change of P_max (and mode) against the setting it
# varies (the defaults, or the grid setting it is 'around'), per case
oat = []
runs = table.set_index(["setting", "case"])
for setting, g in table[~table.grid & (table.setting != "default")].groupby("setting", sort=False):
    around = sm.params.baselines[setting]
    parts = []
    for r in g.itertuples():
        d = runs.loc[(around, r.case)]
        if not r.ok:
            parts.append(f"{r.case} FAILED ({r.status})")
        else:
            parts.append(f"{r.case} {100 * (r.P_max_kN / d.P_max_kN - 1):+.2f} %"
                         + ("" if r.failure_mode == d.failure_mode else f" ({r.failure_mode} failure)")
                         + f" in {r.wall_time_s / d.wall_time_s:.2f} x the time")
    oat.append(f"- {setting}" + ("" if around == "default" else f" (against {around})") + ": " + "; ".join(parts))
unjudged = sorted(set(conv.case) - set(judged))
figures.write_caption(sm.input.templates[1], sm.output.captions[1], cases=", ".join(judged) + (
                          f"; not judged, no converged reference: {', '.join(unjudged)}" if unjudged else ""),
                      tolerance=f"{100 * A['tolerance']:g} %",
                      knee=describe(knee.iloc[0]) if len(knee) else "NONE within the tolerance",
                      numerics=", ".join(sm.params.numerics) or "the scene's own", default=describe("default"),
                      oat="\n".join(oat))
figures.accuracy_pareto(table, conv, choice, A["tolerance"], sm.output.pareto)
