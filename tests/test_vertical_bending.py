"""Vertical bending (plane of failure parallel to the bed joints) against
independent reasons: the brittle limit of a bed joint's cracking moment,
(f_tj + sigma_d) Z, and the weakest link of independent bed joints; the
crack along a bed joint; and the scene's refusals.

The specimen: a column of the solid scene's bricks (config/scenes/solid.yaml)
in stack bond, one unit wide, 12 courses, supports 1.5 course heights from
its ends and loads 3 course heights apart: three bed joints in the
constant-moment zone, three in each shear span.  Stack bond and one unit
wide so that every bed joint bears over the whole section (a toothed end
lifts the stress where a lap ends); elastic units (the joints crack);
brittle joints: G_I = 0.1 N/m, opening 1 um at most past f_tj."""
import copy

import numpy as np
import pytest
from scipy import stats

from masonrydem.errors import InputError
from masonrydem.scene import build_scene
from masonrydem.scene.files import read_scene
from masonrydem.specimen import outcome_row, simulate, simulate_many
from masonrydem.specimen.classify import bed_planes

COURSES = 12


def column(ft=0.2e6, pressure=0.0, refine=2, **bending):
    """The brittle column as a scene mapping; ``ft`` one value or one per
    joint (bed joints bottom up)."""
    raw = read_scene("config/scenes/solid.yaml")
    raw["geometry"].update(courses=COURSES, units_per_course=1, bond_offset=0.0)
    raw["physics"] = {"blocks": "elastic"}
    joints = raw["materials"]["joints"]
    joints.pop("GI_per_ft")
    joints.update(GI="0.1 N/m")
    if np.ndim(ft):
        raw["materials"]["per_joint"] = {"ft": [float(f) for f in ft]}
    else:
        joints["ft"] = float(ft)
    raw["loading"] = {"precompression": {"pressure": pressure},
                      "bending": {"direction": "vertical", "shear_span_units": 3.0, "load_span_units": 3.0,
                                  "rate": 2e-9, "max_displacement": 1e-4, "load_drop": 0.8, **bending}}
    raw["numerics"] = {"subcontact_refine": {"head": 1, "bed": refine}}
    return raw


def section_modulus(scene):
    """Z = b t^2 / 6 of the bed joints' section as modelled (the column's
    modelled unit length, all of it bearing)."""
    g = scene.geometry
    x0, x1 = g.common_span
    return (x1 - x0) * g.unit_width ** 2 / 6.0


def moment_shares(scene):
    """Per bed joint (bottom up), its moment over the constant moment
    between the loads: 1 between them, falling linearly to 0 at the
    supports, 0 outside."""
    b = scene.loading.bending
    H = scene.geometry.modelled_unit[2]
    z = H * np.arange(1, scene.geometry.courses)
    s0, s1 = min(b.supports), max(b.supports)
    return np.clip(np.minimum(z - s0, s1 - z) / b.shear_span, 0.0, 1.0)


def peak_moment(row, scene):
    return 0.5 * row.P_max_kN * 1e3 * scene.loading.bending.shear_span


@pytest.mark.parametrize("refine", [2, 4])
def test_a_brittle_bed_joint_cracks_at_its_tensile_strength_over_the_section_modulus(refine):
    """Without precompression the peak moment of a brittle, uniform
    column is f_tj Z, within 1 % at refinements 2 and 4 of the bed joints'
    sub-contacts (the closed form of a linear stress distribution reaching
    f_tj at the face, and a cracked section that carries less)."""
    scene = build_scene(column(refine=refine))
    row = outcome_row(simulate(scene, progress=False))
    expected = 0.2e6 * section_modulus(scene)
    assert row.status == "load_drop"
    assert peak_moment(row, scene) / expected == pytest.approx(1.0, abs=0.01), (row.P_max_kN, expected)


def test_precompression_adds_to_the_cracking_moment():
    """With sigma_d = 0.05 MPa the stress at the face reaches f_tj at
    M = (f_tj + sigma_d) Z.  A cracked section under compression carries
    load a little longer as the crack grows from one sub-contact through
    the thickness to the next (the more so the nearer sigma_d to f_tj), so
    the discrete section's peak lies above the brittle limit and comes
    down to it as the bed joints' points through the thickness are refined
    and the loading slows: within 1 % at 97 points and 5e-10 m per step
    (docs/formulation.md, 8.1)."""
    excess = []
    for refine, rate in (((1, 4, 1), 2e-9), ((1, 16, 1), 5e-10)):
        scene = build_scene(column(pressure=0.05e6, refine=list(refine), rate=rate))
        row = outcome_row(simulate(scene, progress=False))
        excess.append(peak_moment(row, scene) / ((0.2e6 + 0.05e6) * section_modulus(scene)) - 1.0)
    assert 0.0 <= excess[1] < 0.01 and excess[1] < excess[0], excess


def test_the_peak_is_that_of_the_weakest_bed_joint():
    """Independent joint strengths, f_tj ~ normal(0.2 MPa, cov 0.15) per
    joint, brittle joints, no precompression: the strength S = M_peak / Z
    is min_i f_tj,i / m_i over the bed joints (m_i the joint's share of the
    constant moment), so P(S > s) = prod_i (1 - F(s m_i)) -- for the three
    joints of the constant-moment zone alone, 1 - (1 - F(s))^3 -- and the
    crack runs along the joint that is weakest so.  Checked over 96
    columns by Kolmogorov-Smirnov (p > 0.01), which rejects the single
    joint's distribution F with p < 1e-4 (its power here)."""
    rng = np.random.default_rng(20261129)
    mean, cov, n = 0.2e6, 0.15, 96
    draws = rng.normal(mean, cov * mean, size=(n, COURSES - 1))
    scenes = [build_scene(column(ft=d)) for d in draws]
    shares = moment_shares(scenes[0])
    assert np.count_nonzero(shares == 1.0) == 3
    Z = section_modulus(scenes[0])
    strength, cracked = np.full(n, np.nan), np.full(n, -1)

    def finish(i, outcome, error):
        assert error is None, error
        row = outcome_row(outcome)
        strength[i] = peak_moment(row, scenes[i]) / Z
        planes = bed_planes(outcome.specimen, outcome.state)
        cracked[i] = max(planes, key=planes.get) - 1      # bed joint number, bottom up
        assert "the crack runs along the bed joint between courses" in row.classification

    simulate_many(scenes, finish, lanes=8)
    live = shares > 0

    def cdf(s):
        s = np.atleast_1d(s)[:, None]
        return 1.0 - np.prod(stats.norm.sf(s * shares[live], mean, cov * mean), axis=1)

    weakest = np.argmax(np.where(live, shares, 0.0) / np.where(live, draws, np.inf), axis=1)
    assert np.mean(cracked == weakest) >= 0.95, (cracked, weakest)
    assert stats.kstest(strength, cdf).pvalue > 0.01
    assert stats.kstest(strength, stats.norm(mean, cov * mean).cdf).pvalue < 1e-4


@pytest.mark.parametrize("change, field", [
    (lambda b, g: b.update(supports_x=[0.1, 0.8]), "loading.bending.supports_x"),
    (lambda b, g: b.update(section_height=0.3), "loading.bending.section_height"),
    (lambda b, g: g.update(courses=2), "geometry.courses"),
    (lambda b, g: [b.pop("shear_span_units"), b.pop("load_span_units"),       # both loads on course 7 (0.39-0.455 m)
                   b.update(supports_z=[0.1, 0.7], loads_z=[0.40, 0.44])], "loading.bending.loads_z"),
    (lambda b, g: b.update(direction="diagonal"), "loading.bending.direction"),
    (lambda b, g: b.update(load_span_units=1.5), "loading.bending.loads_z"),     # one bed joint between the loads
    (lambda b, g: g.update(bond_offset=0.5), "geometry.units_per_course"),       # one toothed unit, half a unit bearing
    (lambda b, g: g.update(bond_offset=0.75, units_per_course=2), "geometry.units_per_course"),  # 1.25 units
])
def test_a_vertical_test_the_wallette_cannot_take_is_refused_naming_the_key(change, field):
    raw = copy.deepcopy(column())
    change(raw["loading"]["bending"], raw["geometry"])
    with pytest.raises(InputError) as e:
        build_scene(raw)
    assert e.value.field == field, str(e.value)


def test_straight_ends_cut_the_shifted_courses_into_bats():
    """With straight ends every course spans the same length: a shifted
    course ends in bats of b L and (1 - b) L around its whole units, and
    the joints follow (a head joint between neighbours, a bed plane under
    each unit above the first course)."""
    scene = build_scene("config/scenes/solid_vertical.yaml")
    g = scene.geometry
    L, n = g.modelled_unit[0], g.units_per_course
    for k in range(g.courses):
        spans = g.unit_spans(k)
        assert spans[0][0] == 0.0 and spans[-1][1] == pytest.approx(n * L, abs=1e-12)
        assert all(a[1] == b[0] for a, b in zip(spans, spans[1:]))
        lengths = sorted(round((x1 - x0) / L, 12) for x0, x1 in spans)
        assert lengths == ([0.5, 0.5] + [1.0] * (n - 1) if k % 2 else [1.0] * n)
    counts = [n + k % 2 for k in range(g.courses)]
    assert g.n_units == sum(counts) == len(scene.materials.units.E)
    assert len(g.joints) == sum(c - 1 for c in counts) + sum(counts[1:]) == len(scene.materials.joints.ft)
    assert g.common_span == pytest.approx((0.0, n * L)) and g.bed_length == pytest.approx(n * L - 0.01)


def test_a_straight_ended_bonded_wallette_reaches_the_brittle_limit():
    """The committed vertical scene, running bond with straight ends and
    brittle uniform joints: its bed joints bear over the whole width, so
    its peak is f_tj Z within 1 % as the column's is (with toothed ends a
    lap's end lifts the stress there and the peak falls short:
    docs/formulation.md, 8.1)."""
    raw = read_scene("config/scenes/solid_vertical.yaml")
    raw["materials"]["joints"].pop("GI_per_ft")
    raw["materials"]["joints"]["GI"] = "0.1 N/m"
    raw["loading"]["bending"].update(rate=2e-9, max_displacement=1e-4, past_peak=None)
    raw["numerics"] = {"subcontact_refine": {"bed": 2}}
    scene = build_scene(raw)
    row = outcome_row(simulate(scene, progress=False))
    assert row.status == "load_drop" and "the crack runs along the bed joint" in row.classification
    assert peak_moment(row, scene) / (0.2e6 * section_modulus(scene)) == pytest.approx(1.0, abs=0.01)
