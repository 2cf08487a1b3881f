"""A stage's tables as pages of the report (HTML: the report shows them in
place; the CSVs stay the data): src/masonrydem/report/tables.py."""
import sys
from pathlib import Path

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import tables  # noqa: E402

for name, title in sm.params.titles.items():
    table = pd.read_csv(sm.input[name])
    # the correlations' columns are named after the inputs, in their units
    Path(sm.output[name]).write_text(tables.html_table(table, title, units=name != "correlations"))
    print(name, table.shape)
