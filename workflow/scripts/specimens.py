"""The further specimens' table, figure and caption (issue 7)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.figures import write_caption  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402
from masonrydem.validation import specimen_figure, specimen_table  # noqa: E402

cases = list(sm.params.cases)
results = {c: pd.read_parquet(p).iloc[0] for c, p in zip(cases, sm.input.results)}
curves = {c: pd.read_parquet(p) for c, p in zip(cases, sm.input.curves)}
scenes = {c: load_scene(sm.params.cases[c]["scene"], sm.params.cases[c]["overrides"]) for c in cases}
table = specimen_table(results, curves, scenes)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
specimen_figure(table, curves, sm.output.figure)
lines = []
for r in table.itertuples():
    line = (f"- {r.case} ({r.test}, sigma_v {r.sigma_v_mpa:g} MPa, f_tj {r.f_tj_mpa:g} MPa): P_max {r.P_max_kN:.2f} kN "
            f"at {r.disp_at_peak_mm:.3f} mm, stress {r.stress_mpa:.3f} MPa, {r.failure_mode} failure, {r.status}")
    if r.test == "triplet":
        line += (f"; peak against c + sigma tan phi = {r.peak_closed_form_mpa:.3f} MPa: {100 * r.peak_error:+.1f} %; "
                 f"at the end {r.end_stress_mpa:.3f} MPa against sigma tan phi = {r.residual_closed_form_mpa:.3f} MPa: "
                 f"{100 * r.residual_error:+.1f} %")
    lines.append(line)
write_caption(sm.input.template, sm.output.caption, lines="\n".join(lines))
