"""One wallette (or another specimen) in one test: a typed scene
(masonrydem.scene) built into a solver model (build.py: the one place a
scene's names become the solver's types), run through its test
(protocol.py), classified (classify.py) and written as one result row and
curve (row.py), with its 3-D state (state.py, imported on its own: it
loads pyvista)."""
from .build import Specimen
from .protocol import Outcome, simulate, simulate_many
from .row import Row, curve, error_row, outcome_row, read_json, write, write_json

# build and classify are modules of this folder and their one function each
# (specimen.build.build, specimen.classify.classify): not shadowed here
__all__ = ["Outcome", "Row", "Specimen", "build", "classify", "curve", "error_row", "outcome_row", "read_json",
           "simulate", "simulate_many", "state", "write", "write_json"]
