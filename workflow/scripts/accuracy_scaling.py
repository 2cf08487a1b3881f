"""How run time grows with the number of units and with cells per edge."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem import accuracy, figures  # noqa: E402

units = pd.concat([pd.read_parquet(p) for p in sm.input.scaling], ignore_index=True)
units["courses"] = [int(p.split("/courses")[-1].split("/")[0]) for p in sm.input.scaling]
runs = pd.read_csv(sm.input.runs)
# cells: the refinement path's meshes, first case, coarsest sub-contact refinement
first = runs.case.iloc[0]
cells = runs[(runs.case == first) & runs.setting.isin(sm.params.settings) & runs.ok]
tables = {"units": units, "cells": cells.sort_values("cells_n").assign(cells=lambda t: t.cells_n)}   # along a unit
rows, fits = [], {}
for name, t in tables.items():
    t["us_per_step"] = t.wall_time_s / t.steps * 1e6
    for col in ("wall_time_s", "us_per_step", "tets"):
        a, k = accuracy.power_fit(t[name], t[col])
        fits[(name, col)] = (a, k)
        rows.append(dict(against=name, quantity=col, exponent=k, coefficient=a,
                         points=" ".join(f"{xx:g}:{yy:.4g}" for xx, yy in zip(t[name], t[col]))))
table = pd.DataFrame(rows)
table.to_csv(sm.output.table, index=False, float_format="%.6g")
print(table.to_string())
fit_text = "; ".join(f"{r.quantity} ~ {r.against}^{r.exponent:.2f}" for r in table.itertuples()
                     if r.quantity != "tets")
figures.write_caption(sm.input.template, sm.output.caption, courses=", ".join(str(c) for c in units.courses)
                      if "courses" in units else "", fits=fit_text)
figures.accuracy_scaling(tables["units"], tables["cells"], fits, sm.output.figure)
