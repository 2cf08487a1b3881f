"""Further standard specimens as scenes: direct tension parallel
to the bed joints and the triplet shear test, against closed forms."""
import math

import numpy as np
import pytest
from runs import run_scene

from masonrydem.errors import InputError
from masonrydem.scene import joint_kn
from masonrydem.scene import build_scene
from masonrydem.analysis.validation import initial_stiffness

TENSION = "config/scenes/tension.yaml"
TRIPLET = "config/scenes/triplet.yaml"
COARSE = ["numerics.cells=[2, 1, 1]"]


def _section(scene):
    """Modelled unit length and the area of a head joint (height x width)."""
    g = scene.geometry
    t = g.joint_thickness
    return g.unit_length + t, (g.unit_height + t) * g.unit_width


def _wall(values):
    """The one value of a property every unit (joint) has: the wall's."""
    return np.unique(values).item()


def test_stack_bonded_tension_matches_the_series_springs():
    """Stack bond (no overlap): every course is a chain of units and head
    joints in series, uniformly stressed (the platens hold x only; the bed
    joints carry no shear because the courses stretch alike).  Stiffness
    n_c A / (n_u L / E + (n_u - 1) / k_n), and the peak is reached when the
    head joints reach f_tj: P_max = n_c A f_tj.  The peak's quasi-static
    lag is proportional to the rate and equals the unbalanced-force ratio
    at the peak (measured: +0.33 %, +0.17 %, +0.08 % at 4e-9, 2e-9 (the
    scene's rate), 1e-9 m per step)."""
    sc = build_scene(TENSION, COARSE + ["geometry.bond_offset=0.0", "geometry.courses=2"])
    row, curve, _, _ = run_scene(sc)
    L, A = _section(sc)
    n_c, n_u = sc.geometry.courses, sc.geometry.units_per_course
    E, ft = _wall(sc.materials.units.E), _wall(sc.materials.joints.ft)
    kn = joint_kn(E, sc.materials.joints.Em_ratio, sc.geometry.joint_thickness)
    K = n_c * A / (n_u * L / E + (n_u - 1) / kn)              # N/m
    assert row["ok"], row["message"]
    assert row["failure_mode"] == "joint"
    assert row["P_max_kN"] * 1e3 == pytest.approx(n_c * A * ft, rel=5e-3)
    assert initial_stiffness(curve) * 1e6 == pytest.approx(K, rel=1e-2)   # kN/mm -> N/m


@pytest.mark.parametrize("blocks, overrides, peak_tol", [
    # rigid units: the joints slip uniformly, every point reaches its
    # strength at once
    ("rigid", [], 2e-3),
    # deformable units: the shear stress is not uniform along the joint;
    # with a large mode-II fracture energy every point still reaches its
    # strength before any softens much
    ("elasto-plastic", ["materials.joints.GII_ratio=1000.0"], 1e-2),
])
def test_triplet_peak_is_the_coulomb_strength(blocks, overrides, peak_tol):
    """Peak shear stress P / 2A = c + sigma tan(phi)."""
    sc = build_scene(TRIPLET, COARSE + [f"physics.blocks={blocks}", "loading.triplet.max_displacement=1.0e-4"]
                    + overrides)
    row, _, _, _ = run_scene(sc)
    j, sigma = sc.materials.joints, sc.loading.precompression.pressure
    assert row["status"] in ("displacement_limit", "load_drop"), row["message"]
    assert row["strength_mpa"] * 1e6 == pytest.approx(
        j.c_ratio * _wall(j.ft) + sigma * math.tan(math.radians(_wall(j.phi))), rel=peak_tol)


def test_triplet_residual_is_friction():
    """Once the cohesion has softened away (slip beyond 2 G_II / c), the
    joints carry sigma tan(phi): the end of the curve.  The quasi-static
    lag grows with the rate (measured at 1 mm: +0.85 % at 1e-8 m per
    step, +0.32 % at 4e-9, +0.02 % at the scene's 2e-9)."""
    sc = build_scene(TRIPLET, COARSE + ["loading.precompression.pressure=0.3e6"])
    row, curve, _, _ = run_scene(sc)
    L, _ = _section(sc)
    j, sigma = sc.materials.joints, sc.loading.precompression.pressure
    A = L * sc.geometry.unit_width
    slip_softened = 2 * j.GII_ratio * _wall(j.GI) / (j.c_ratio * _wall(j.ft))
    assert row["status"] == "displacement_limit", row["message"]
    assert curve["displacement_mm"].iloc[-1] * 1e-3 > 1.5 * slip_softened
    assert curve["load_kN"].iloc[-1] * 1e3 == pytest.approx(2 * A * sigma * math.tan(math.radians(_wall(j.phi))),
                                                            rel=5e-3)


def test_a_peak_within_the_velocity_ramp_is_flagged():
    """The joints reach their strength at a slip (c + sigma tan phi) / k_s
    of 7.5 microns; a ramp of 2000 steps at 1e-8 m per step covers 10
    microns: the peak falls within the ramp, where a peak does not count,
    and the run must say so instead of reporting a later, lower load."""
    sc = build_scene(TRIPLET, COARSE + ["physics.blocks=rigid", "loading.triplet.rate=1.0e-8",
                                       "loading.triplet.ramp_steps=2000", "loading.triplet.max_displacement=1.0e-4"])
    j, sigma = sc.materials.joints, sc.loading.precompression.pressure
    kn = joint_kn(_wall(sc.materials.units.E), j.Em_ratio, sc.geometry.joint_thickness)
    slip = (j.c_ratio * _wall(j.ft) + sigma * math.tan(math.radians(_wall(j.phi)))) / (j.ks_ratio * kn)
    assert slip < 0.5 * 2000 * 1.0e-8
    row, _, _, _ = run_scene(sc)
    assert row["status"] == "peak_in_ramp" and not row["ok"], row["message"]


@pytest.mark.parametrize("override, field", [
    ("geometry.courses=4", "geometry.courses"),
    ("geometry.units_per_course=2", "geometry.units_per_course"),
    ("loading.test=shear", "loading.test"),
    ("loading.triplet.rate=-1.0e-9", "loading.triplet.rate"),
])
def test_a_wrong_specimen_is_refused_naming_the_field(override, field):
    with pytest.raises(InputError) as e:
        build_scene(TRIPLET, [override])
    assert e.value.field == field
