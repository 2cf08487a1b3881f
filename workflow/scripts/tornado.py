"""The model-form study's tornado chart, from its summary."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import figures as F  # noqa: E402

F.tornado(pd.read_csv(sm.input.table), sm.output.figure, sm.params.titles)
