"""Latin Hypercube samples of the study and the achieved correlations."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

from masonrydem import captions  # noqa: E402
from masonrydem.results import write_json  # noqa: E402
from masonrydem.sampling import records, sampling_check, study_samples  # noqa: E402

nonspatial, spatial, achieved = study_samples(sm.params.n_samples, sm.params.seed)
write_json(sm.output.nonspatial, records(nonspatial))
write_json(sm.output.spatial, records(spatial))
check = sampling_check(nonspatial, achieved)
check.to_csv(sm.output.check, index=False, float_format="%.4g")
print(check.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.sampling_check(check, achieved))
