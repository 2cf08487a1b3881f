"""Deterministic validation: table and load-displacement figure."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import pandas as pd  # noqa: E402

from masonrydem.figures import write_caption  # noqa: E402
from masonrydem.validation import figure, summary_table  # noqa: E402

runs = [p.split("/")[-2] for p in sm.input.results]
results = {r: pd.read_parquet(p).iloc[0] for r, p in zip(runs, sm.input.results)}
curves = {r: pd.read_parquet(p) for r, p in zip(runs, sm.input.curves)}
table = summary_table(results, curves)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
figure(table, curves, sm.output.figure)
lines = [f"- {r.case}, sigma_v = {r.sigma_v_mpa:g} MPa: **P_max {r.P_max_kN:.3f} kN** at {r.disp_at_peak_mm:.3f} mm "
         f"({r.strength_mpa:.3f} MPa, initial stiffness {r.initial_stiffness_kN_per_mm:.1f} kN/mm), "
         f"{r.failure_mode} failure, {r.status}, {r.P_max_change_vs_reference_pct:+.2f} % against the reference"
         for r in table.itertuples()]
write_caption(sm.input.template, sm.output.caption, lines="\n".join(lines))
