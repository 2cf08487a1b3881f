"""The report's landing page, from the study's tables."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions, landing  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
level, _ = of_study(sm.params.analysis)
card = landing.read_card(sm.input.card[0] if sm.input.card else None)
values = landing.landing(runs, pd.read_csv(sm.input.statistics), int((~runs.ok).sum()), level, sm.params.report,
                         card, sm.params.band)
captions.write_caption(sm.input.template, sm.output[0], **values)
print(values["paper"])
