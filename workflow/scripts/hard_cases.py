"""The hard-cases table (issue 6) and its caption."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.figures import write_caption  # noqa: E402
from masonrydem.validation import hard_cases_table  # noqa: E402

runs = [p.split("/")[-2] for p in sm.input.results]
table = hard_cases_table({r: pd.read_parquet(p).iloc[0] for r, p in zip(runs, sm.input.results)}, sm.config)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
lines = [f"- {r.run}: {r.status}, **P_max {r.P_max_kN:.3f} kN**, {r.failure_mode} failure "
         f"(expected: {r.expect}{'' if r.mode_as_expected else ', NOT MET'}), {r.steps} steps, "
         f"ratio at the peak {r.ratio_at_peak:.4f}, post-peak {r.post_peak}"
         + ("" if pd.isna(r.half_rate_change_pct) else f", {r.half_rate_change_pct:+.2f} % against {r.case}")
         for r in table.itertuples()]
unmet = int((~(table.mode_as_expected & table.ok)).sum())
write_caption(sm.input.template, sm.output.caption, lines="\n".join(lines), n=len(table), unmet=unmet)
