"""Statistics and correlations of the study's runs."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.analysis.statistics import of_study, study_tables  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
level, inputs = of_study(sm.params.analysis)      # the swept setting, the random inputs' columns
# every statistic with its 95 % interval (columns <statistic>_lo, _hi)
st, corr, inc = study_tables(runs, **sm.params.bootstrap, inputs=list(inputs), level=level)
st.to_csv(sm.output.statistics, index=False, float_format="%.4g")
corr.to_csv(sm.output.correlations, index=False, float_format="%.4g")
low, high = runs[level.column].min(), runs[level.column].max()
inc.assign(sigma_from=low, sigma_to=high).to_csv(sm.output.increase, index=False, float_format="%.4g")
print(st.to_string())
captions.write_captions(sm.input.templates, sm.output.captions,
                        captions.statistics(runs, st, corr, inc, level, list(inputs), sm.params.report))
