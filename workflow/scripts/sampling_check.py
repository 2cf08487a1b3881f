"""The achieved correlations and distributions of the study's samples
(drawn again: the same seed gives the same samples)."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

from masonrydem.report import captions  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402
from masonrydem.study.sampling import sampling_check  # noqa: E402

study = plan.study(sm.config)
wallettes, achieved = study.wallette_draw
check = sampling_check(wallettes, achieved, study.variables)
check.to_csv(sm.output.check, index=False, float_format="%.4g")
print(check.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.sampling_check(check, achieved,
                                                                                study.correlations))
