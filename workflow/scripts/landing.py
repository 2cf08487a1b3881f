"""The report's landing page, from the study's tables."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions, landing  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402

import os  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
summary = sm.params.band
band = landing.modelform_band(pd.read_csv(summary)) if summary and os.path.isfile(summary) else None
level, _ = of_study(sm.params.analysis)
card = landing.read_card(sm.input.card[0] if sm.input.card else None)
values = landing.landing(runs, pd.read_csv(sm.input.statistics), int((~runs.ok).sum()), level, sm.params.report,
                         card, band)
captions.write_caption(sm.input.template, sm.output[0], **values)
print(values["paper"])
