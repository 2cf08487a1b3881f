"""The accuracy study's figures, from its tables alone (runs.csv,
convergence.csv, choice.csv, scaling.csv): a figure can be redrawn
without the accuracy runs, which are not committed."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import figures  # noqa: E402

figures.accuracy_pareto(pd.read_csv(sm.input.runs), pd.read_csv(sm.input.convergence), pd.read_csv(sm.input.choice),
                        sm.params.tolerance, sm.output.pareto)
figures.accuracy_scaling(pd.read_csv(sm.input.scaling), sm.output.scaling)
