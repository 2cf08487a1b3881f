"""Latin Hypercube samples of the study and the achieved correlations."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

import numpy as np  # noqa: E402

from masonrydem.figures import write_caption  # noqa: E402
from masonrydem.runner import atomic_write  # noqa: E402
from masonrydem.sampling import STUDY_VARIABLES, study_samples  # noqa: E402

nonspatial, spatial, achieved = study_samples(sm.params.n_samples, sm.params.seed)
atomic_write(sm.output.nonspatial, lambda p: nonspatial.to_parquet(p, index=False))
atomic_write(sm.output.spatial, lambda p: spatial.to_parquet(p, index=False))
names = [v.name for v in STUDY_VARIABLES]
rows = []
for v in STUDY_VARIABLES:
    x = nonspatial[v.name]
    rows.append(dict(variable=v.name, distribution=v.dist, mean_target=v.mean, mean_sample=x.mean(),
                     cov_target=v.cov, cov_sample=x.std(ddof=1) / x.mean(),
                     **{f"corr_{n}": achieved[names.index(v.name), k] for k, n in enumerate(names)}))
check = pd.DataFrame(rows)
check.to_csv(sm.output.check, index=False, float_format="%.4g")
print(check.to_string())
i, j = names.index("E_b"), names.index("f_tu")
others = np.abs(achieved - np.eye(len(names)))
others[i, j] = others[j, i] = 0.0
write_caption(sm.input.template, sm.output.caption, corr=achieved[i, j], other=others.max(),
              mean_dev=100 * (check.mean_sample / check.mean_target - 1).abs().max(),
              cov_dev=100 * (check.cov_sample / check.cov_target - 1).abs().max())
