"""Statistics and correlations of the study's runs."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.analysis import correlations, increase, statistics  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
st = statistics(runs)
st.to_csv(sm.output.statistics, index=False, float_format="%.4g")
correlations(runs).to_csv(sm.output.correlations, index=False, float_format="%.4g")
levels = sorted(runs.sigma_v_mpa.unique())
increase(st, levels[0], levels[-1]).assign(sigma_from=levels[0], sigma_to=levels[-1]).to_csv(
    sm.output.increase, index=False, float_format="%.4g")
print(st.to_string())
