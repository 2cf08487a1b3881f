"""Sobol indices of the study's strength on a Gaussian process of its runs."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.report import figures as F  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.analysis import sensitivity as S  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402
from masonrydem.scene import to_shown  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
spec = sm.params.analysis
level, _ = of_study(spec)
study = plan.study(sm.config)
# the random inputs in the study file's order (the order decides how a correlated pair splits)
variables = [v for v in study.variables if spec["columns"].get(v.name) in runs]
to_inputs = S.input_map(variables, study.correlations, {v.name: to_shown(1.0, study.units[v.name]) for v in variables})
table = S.sensitivity_table(runs, level, [spec["columns"][v.name] for v in variables], to_inputs,
                            seed=sm.params.seed, jobs=sm.threads)
table = S.with_pearson(table, pd.read_csv(sm.input.correlations), level)
table.to_csv(sm.output.table, index=False, float_format="%.4g")
if S.no_indices(table):
    F.placeholder(S.no_indices(table), sm.output.figure)
else:
    S.figure(table, sm.output.figure, level)
print(table.to_string())
captions.write_caption(sm.input.template, sm.output.caption,
                       **S.caption_values(table, level, variables, study.correlations))
