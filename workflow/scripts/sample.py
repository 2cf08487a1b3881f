"""Latin Hypercube samples of the study (their check: sampling_check.py)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

from masonrydem.results import write_json  # noqa: E402
from masonrydem.sampling import records, study_samples  # noqa: E402

nonspatial, spatial, _ = study_samples(sm.params.n_samples, sm.params.seed)
write_json(sm.output.nonspatial, records(nonspatial))
write_json(sm.output.spatial, records(spatial))
print(len(nonspatial), "non-spatial and", len(spatial), "spatial samples")
