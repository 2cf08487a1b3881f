"""The report's landing page, from the study's tables."""
import os
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions, landing  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402
from masonrydem.pipeline import plan  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
# the model-form study's band of P_max changes, if that study has run when
# the page is made: not an input (its own target runs it; `all` never does)
summary = os.path.join(sm.config["results"], "modelform", "summary.csv")
band = landing.modelform_band(pd.read_csv(summary)) if sm.config.get("modelform") and os.path.isfile(summary) else None
level, _ = of_study(sm.params.analysis)
card = landing.read_card(sm.input.card[0] if sm.input.card else None)
values = landing.landing(runs, pd.read_csv(sm.input.statistics), int((~runs.ok).sum()), level, sm.params.report,
                         landing.source(sm.input.paper[0] if sm.input.paper else None, sm.params.study_file),
                         card, band, plan.study(sm.config).direction)
captions.write_caption(sm.input.template, sm.output[0], **values)
print(values["paper"])
