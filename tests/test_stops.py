"""The stop rule 'past_peak' (stops.stop_rule), which ends the
test stage as soon as its peak is certain, on rows made by hand; and the
scene setting that asks for it."""
import numpy as np
import pytest

from masonrydem.errors import InputError
from masonrydem.dem.history import PEAK_UNBALANCE, History, Peak
from masonrydem.scene import build_scene
from masonrydem.dem.stops import Stops, stop_rule

PEAK = Peak(load=10e3, disp=1.0e-3, step=1000, ratio=0.0, unbalance=0.0)
RULE = Stops(disp_limit=5e-3, load_drop=0.2, monitor="load", balance="support", past_peak=(0.05, 1e-4, 2e-4))


def _row(load, disp, support=None):
    """A chunk's last row: the load monitor (group 0) and its balancing
    support (group 1, by default the reaction that balances the load)."""
    support = -load if support is None else support
    return History(step=np.array([2000]), ratio=np.array([1e-3]), kinetic_energy=np.array([0.0]),
                   force=np.array([[load, support]]), disp=np.array([[disp, 0.0]]), loading=np.array([True]),
                   monitors=("load", "support"))


@pytest.mark.parametrize("load,beyond,support,status", [
    (9.4e3, 1.0e-4, None, "past_peak"),        # far enough, 6 % down and balanced
    (9.6e3, 1.0e-4, None, None),               # only 4 % down
    (9.4e3, 0.9e-4, None, None),               # not yet 0.1 mm beyond the peak
    (9.4e3, 1.5e-4, -9.4e3 * (1 - 2 * PEAK_UNBALANCE), None),   # down, but out of balance (a snap)
    (9.99e3, 2.0e-4, -5e3, "past_peak"),       # 0.2 mm beyond the peak: certain, whatever the load
    (1.5e3, 0.5e-4, None, "load_drop"),        # the other rules first
])
def test_past_peak_holds_when_the_peak_is_certain(load, beyond, support, status):
    end = stop_rule(RULE, 0, _row(load, PEAK.disp + beyond, support), PEAK, 1)
    assert (end[0] if end else None) == status


def test_without_a_peak_or_the_rule_nothing_stops_past_it():
    assert stop_rule(RULE, 0, _row(1e3, 3e-3), None, 1) is None
    assert stop_rule(RULE._replace(past_peak=None), 0, _row(9e3, PEAK.disp + 3e-4), PEAK, 1) is None


def test_the_scene_setting_takes_lengths_with_units():
    scene = build_scene("config/scenes/willis.yaml", ["loading.bending.past_peak={drop: 0.05, after: 0.1 mm, "
                                                     "at_most: 0.2 mm}"])
    assert scene.loading.drive.past_peak == (0.05, 1e-4, 2e-4)
    assert build_scene("config/scenes/willis.yaml").loading.drive.past_peak is None
    with pytest.raises(InputError) as e:       # the drop after the peak is read over 0.1 mm: it must get there
        build_scene("config/scenes/willis.yaml", ["loading.bending.past_peak={drop: 0.05, after: 0.05 mm, "
                                                 "at_most: 0.2 mm}"])
    assert "loading.bending.past_peak.after" in str(e.value)
