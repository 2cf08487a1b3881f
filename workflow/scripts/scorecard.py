"""The source paper side by side: the scorecard and its figure."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402
import yaml  # noqa: E402

from masonrydem.report import captions  # noqa: E402
from masonrydem.report import figures as F  # noqa: E402
from masonrydem.analysis import validation as V  # noqa: E402

with open(sm.input.paper) as f:
    paper = yaml.safe_load(f)
card = V.paper_comparison(paper, pd.read_parquet(sm.input.runs), pd.read_csv(sm.input.statistics),
                          pd.read_csv(sm.input.increase), pd.read_csv(sm.input.equations), sm.params.analysis,
                          **sm.params.bootstrap)
card.to_csv(sm.output.table, index=False, float_format="%.4g")
F.paper_comparison(card, sm.output.figure)
print(card.to_string())
captions.write_caption(sm.input.template, sm.output.caption, **captions.paper_comparison(card))
