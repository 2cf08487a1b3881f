"""One simulation of a scene for the tests: the row as a mapping, the curve
as a frame, the specimen and the final state."""
from dataclasses import asdict

import pandas as pd

from masonrydem.protocol import simulate
from masonrydem.results import curve, outcome_row


def run_scene(scene):
    """(row dict, curve DataFrame, specimen, final State) of a typed scene."""
    outcome = simulate(scene, progress=False)
    return asdict(outcome_row(outcome)), pd.DataFrame(curve(outcome)), outcome.specimen, outcome.state
