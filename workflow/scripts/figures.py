"""Figures of the study's statistics."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem import analysis, captions  # noqa: E402
from masonrydem import figures as F  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
curves = pd.read_parquet(sm.input.curves)
stats = pd.read_csv(sm.input.statistics)
corr = pd.read_csv(sm.input.correlations)
level, inputs = analysis.of_study(sm.params.analysis)     # the swept setting, the random inputs' columns and means
sv_scatter = analysis.scatter_level(runs, level=level)
F.running_mean(runs, sm.output.running_mean, level)
F.brick_share(stats, sm.output.brick_share, level)
F.correlation_vs_sigma(corr, sm.output.correlation, level, list(inputs))
F.scatter_deviation(runs, sv_scatter, sm.output.scatter, level, inputs)
F.curves_by_mode(runs, curves, [runs[level.column].min(), runs[level.column].max()], sm.output.curves, level)
captions.write_captions(sm.input.templates, sm.output.captions,
                        captions.study_figures(runs, stats, corr, sv_scatter, level, list(inputs)))
