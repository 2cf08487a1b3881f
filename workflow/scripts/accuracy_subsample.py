"""The study's conclusions on a subsample: default against fine settings."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem import accuracy, figures  # noqa: E402

default = pd.concat([pd.read_parquet(p) for p in sm.input.default], ignore_index=True)
fine = pd.concat([pd.read_parquet(p) for p in sm.input.fine], ignore_index=True)
table = accuracy.compare_subsample(default, fine)
table.to_csv(sm.output.table, index=False, float_format="%.6g")
print(table.T.to_string())
merged = default.merge(fine, on=["sigma_v_mpa", "sample"], suffixes=("_default", "_fine"))
merged = merged[merged.ok_default & merged.ok_fine]


def num(x, spec):
    """A number for the caption; a COV of one run (or a mean of none) is
    undefined and says so instead of printing nan."""
    return "undefined" if pd.isna(x) else format(x, spec)


lines = [f"- {r.sigma_v_mpa:g} MPa, {r.runs} runs ({r.excluded} excluded): mean P_max {num(r.mean_kN_default, '.3f')} "
         f"kN default, {num(r.mean_kN_fine, '.3f')} kN fine ({num(100 * r.mean_diff, '+.1f')} %); COV "
         f"{num(r.cov_default, '.3f')} default, {num(r.cov_fine, '.3f')} fine; brick failures {r.brick_default} "
         f"default, {r.brick_fine} fine; same mode in {r.same_mode} of {r.runs}; P_max default/fine "
         f"{num(r.ratio_mean, '.3f')} (COV {num(r.ratio_cov, '.3f')})"
         for r in table.itertuples()]
figures.write_caption(sm.input.template, sm.output.caption, n=int(table.runs.max() + table.excluded.max()),
                      levels=", ".join(f"{v:g}" for v in table.sigma_v_mpa),
                      fine=", ".join(sm.params.fine), lines="\n".join(lines))
figures.accuracy_subsample(merged, sm.output.figure)
