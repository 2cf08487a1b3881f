"""The reduced models' table (issue 7) and its caption."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.figures import write_caption  # noqa: E402
from masonrydem.validation import reduced_table  # noqa: E402

runs = [p.split("/")[-2].rsplit("_", 1) for p in sm.input.results]
table = reduced_table({(c, m): pd.read_parquet(p).iloc[0] for (c, m), p in zip(runs, sm.input.results)},
                      sm.params.tolerance)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
lines = []
for case, g in table.groupby("case", sort=False):
    full = g[g.model == "full"].iloc[0]
    parts = [f"full {full.P_max_kN:.3f} kN ({full.failure_mode}, {full.wall_time_s:.1f} s)"]
    parts += [f"{r.model} {r.P_max_kN:.3f} kN ({r.change_pct:+.1f} %, {r.failure_mode}, {r.speedup:.1f} x faster"
              f"{', good enough' if r.good_enough else ''})" for r in g[g.model != "full"].itertuples()]
    lines.append(f"- {case} (sigma_v {full.sigma_v_mpa:g} MPa, f_tj {full.f_tj_mpa:g} MPa): " + "; ".join(parts))
good = table[(table.model != "full") & table.good_enough]
write_caption(sm.input.template, sm.output.caption, lines="\n".join(lines),
              tolerance=f"{100 * sm.params.tolerance:g} %",
              good=", ".join(f"{r.model} on {r.case}" for r in good.itertuples()) or "none")
