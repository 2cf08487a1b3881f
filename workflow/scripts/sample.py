"""Latin Hypercube samples of the study and the achieved correlations."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

from masonrydem import captions  # noqa: E402
from masonrydem.runner import atomic_write  # noqa: E402
from masonrydem.sampling import sampling_check, study_samples  # noqa: E402

nonspatial, spatial, achieved = study_samples(sm.params.n_samples, sm.params.seed)
atomic_write(sm.output.nonspatial, lambda p: nonspatial.to_parquet(p, index=False))
atomic_write(sm.output.spatial, lambda p: spatial.to_parquet(p, index=False))
check = sampling_check(nonspatial, achieved)
check.to_csv(sm.output.check, index=False, float_format="%.4g")
print(check.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.sampling_check(check, achieved))
