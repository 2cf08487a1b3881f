"""Deterministic validation: table and load-displacement figure."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import pandas as pd  # noqa: E402

from masonrydem.validation import figure, summary_table  # noqa: E402

runs = [p.split("/")[-2] for p in sm.input.results]
results = {r: pd.read_parquet(p).iloc[0] for r, p in zip(runs, sm.input.results)}
curves = {r: pd.read_parquet(p) for r, p in zip(runs, sm.input.curves)}
table = summary_table(results, curves)
table.to_csv(sm.output.table, index=False, float_format="%.5g")
print(table.to_string())
figure(table, curves, sm.output.figure)
