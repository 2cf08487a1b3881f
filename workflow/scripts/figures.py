"""Figures of the study's statistics."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from masonrydem import figures as F  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
curves = pd.read_parquet(sm.input.curves)
stats = pd.read_csv(sm.input.statistics)
corr = pd.read_csv(sm.input.correlations)
levels = np.sort(runs.sigma_v_mpa.unique())
F.running_mean(runs, sm.output.running_mean)
F.brick_share(stats, sm.output.brick_share)
F.correlation_vs_sigma(corr, sm.output.correlation)
F.scatter_deviation(runs, levels[np.argmin(np.abs(levels - 0.25))], sm.output.scatter)
F.curves_by_mode(runs, curves, [levels[0], levels[-1]], sm.output.curves)
