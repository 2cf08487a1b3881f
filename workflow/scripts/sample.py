"""Latin Hypercube samples of the study and the achieved correlations."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.runner import atomic_write  # noqa: E402
from masonrydem.sampling import STUDY_VARIABLES, study_samples  # noqa: E402

study = sm.params.study
nonspatial, spatial, achieved = study_samples(study["n_samples"], study["seed"])
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
