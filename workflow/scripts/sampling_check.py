"""The achieved correlations and distributions of the study's samples
(drawn again: the same seed gives the same samples)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

from masonrydem import captions  # noqa: E402
from masonrydem.sampling import sampling_check, study_samples  # noqa: E402

nonspatial, _, achieved = study_samples(sm.params.n_samples, sm.params.seed)
check = sampling_check(nonspatial, achieved)
check.to_csv(sm.output.check, index=False, float_format="%.4g")
print(check.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.sampling_check(check, achieved))
