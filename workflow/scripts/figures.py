"""Figures of the study's statistics."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import statistics  # noqa: E402
from masonrydem.report import captions  # noqa: E402
from masonrydem.report import figures as F  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
curves = pd.read_parquet(sm.input.curves)
stats = pd.read_csv(sm.input.statistics)
corr = pd.read_csv(sm.input.correlations)
spec = sm.params.analysis
level, inputs = statistics.of_study(spec)     # the swept setting, the random inputs' columns and means
names = {col: name for name, col in spec["columns"].items()}
variant = spec["regression_variant"] or spec["variants"][0]      # the scatter plot's
sv_scatter = statistics.scatter_level(runs, level)
F.running_mean(runs, sm.output.running_mean, level)
F.brick_share(stats, sm.output.brick_share, level)
F.correlation_vs_sigma(corr, sm.output.correlation, level, list(inputs), names)
F.scatter_deviation(runs, sv_scatter, sm.output.scatter, level, inputs, variant, names)
F.curves_by_mode(runs, curves, [runs[level.column].min(), runs[level.column].max()], sm.output.curves, level)
captions.write_captions(sm.input.templates, sm.output.captions,
                        captions.study_figures(runs, stats, corr, sv_scatter, level, list(inputs), variant))
