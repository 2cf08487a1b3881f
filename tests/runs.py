"""One simulation of a scene for the tests: the row as a mapping, the curve
as a frame, the specimen and the final state."""

import pandas as pd

from masonrydem.specimen.protocol import simulate
from masonrydem.specimen.row import curve, outcome_row


def run_scene(scene):
    """(row dict, curve DataFrame, specimen, final State) of a typed scene."""
    outcome = simulate(scene, progress=False)
    return outcome_row(outcome).values(), pd.DataFrame(curve(outcome)), outcome.specimen, outcome.state
