"""Failure classification on constructed cases (docs/formulation.md, 11)."""
import math

import pytest
from runs import run_scene

from masonrydem.scene import load_scene

WILLIS = "config/scenes/willis.yaml"


def _run(*overrides):
    row, curve, sp, s = run_scene(load_scene(WILLIS, list(overrides)))
    assert row["ok"], row["message"]
    return row


@pytest.fixture(scope="module")
def brick_case():
    """Strong joints (f_tj = 1.5 MPa, G_I by the study's rule) with weak
    bricks (f_tu = 2 MPa)."""
    return _run("materials.joints.ft=1.5e6", "materials.joints.GI=45.0", "materials.units.ft=2.0e6")


@pytest.fixture(scope="module")
def joint_case():
    """Weak joints (f_tj = 0.1 MPa) with strong bricks (f_tu = 7 MPa)."""
    return _run("materials.joints.ft=0.1e6", "materials.joints.GI=3.0", "materials.units.ft=7.0e6")


def test_strong_joints_weak_bricks_fail_through_bricks(brick_case):
    """Brick failure, and the evidence says why: at least one unit cracked
    through (a layer of cells >= 50 % cracked).  (The load lost within
    0.1 mm after the peak is reported, but does not tell the modes apart:
    18 % here, 15 % for the joint failure below, on 5x2x2 cells.)"""
    r = brick_case
    assert r["failure_mode"] == "brick"
    assert r["cracked_units"] >= 1 and r["unit_crack_fraction"] >= 0.5
    assert r["cracked_brick_volume_frac"] > 0
    assert "cracked through" in r["classification"]


def test_weak_joints_strong_bricks_fail_through_joints(joint_case):
    """Joint failure: no unit cracked through, joints broken."""
    r = joint_case
    assert r["failure_mode"] == "joint"
    assert r["cracked_units"] == 0 and r["unit_crack_fraction"] < 0.5
    assert r["broken_joints"] >= 1


def test_stronger_joints_carry_more(brick_case, joint_case):
    """Monotonicity across the two cases: the wallette with the stronger
    joints carries more."""
    assert brick_case["P_max_kN"] > joint_case["P_max_kN"]



def test_start_up_transient_does_not_stop_the_run():
    """A peak counts only near equilibrium and after the velocity ramp
    (history.py).  On a fine mesh (13x6x6 cells per unit) the stiff
    strips first meet nearly motionless face nodes: during the 2,000-step
    ramp the load rises to kilonewtons at an unbalanced-force ratio above
    0.5 and wavers (measured before this rule: a 2.3 kN spike after 250
    steps that fell to half by step 500 and stopped the run by its load
    drop, long before the real 13 kN peak).  After 1,000 steps, all within
    the ramp: no peak yet, and the run went on to its step limit."""
    row, curve, _, _ = run_scene(load_scene(WILLIS, ["numerics.cells=[13, 6, 6]",
                                                     "loading.bending.max_steps=1000"]))
    dynamic = curve[curve["ratio"] > 0.5]
    assert dynamic["load_kN"].max() > 1.0                                 # the transient is there, dynamic
    assert math.isnan(row["P_max_kN"]) and row["post_peak"] == "none"     # ... it is not a peak
    assert row["status"] == "max_steps"                                   # ... and it did not stop the run
