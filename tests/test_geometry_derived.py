"""The bending test's section comes from the wallette as built,
so that a scene with other bricks or courses gets its own strength."""
import pytest

from masonrydem.scene import read_scene
from masonrydem.scene import validate_scene
from masonrydem.specimen.build import build

WILLIS = "config/scenes/willis.yaml"


def _without_section(*changes):
    raw = read_scene(WILLIS)
    del raw["loading"]["bending"]["section_height"]
    for key, value in changes:
        node = raw
        *head, last = key.split(".")
        for k in head:
            node = node[k]
        node[last] = value
    return validate_scene(raw)


def test_the_willis_section_is_its_built_height_to_the_last_digit():
    """6 courses of 65 mm bricks and 5 bed joints of 10 mm: b = 440 mm, the
    scene's stated value, as the same float (the study's rows unchanged)."""
    assert _without_section().loading.bending.section == 0.44
    assert validate_scene(read_scene(WILLIS)).loading.bending.section == 0.44


@pytest.mark.parametrize("courses,height,joint,b", [(4, 0.065, 0.010, 0.29), (6, 0.076, 0.010, 0.506),
                                                   (8, 0.052, 0.012, 0.5)])
def test_another_wallette_gets_its_own_section(courses, height, joint, b):
    scene = _without_section(("geometry.courses", courses), ("geometry.unit.height", height),
                             ("geometry.joint_thickness", joint))
    assert scene.loading.bending.section == pytest.approx(b, rel=1e-12)
    # the strength of a load P is M / Z of that section: 6 (P a / 2) / (b h^2)
    sp = build(scene)
    a, h = 0.410 - 0.135, 0.114
    assert sp.strength(10e3) == pytest.approx(6 * 10e3 * a / 2 / (b * h * h), rel=1e-12)


def _spans(*changes):
    raw = read_scene(WILLIS)
    bend = raw["loading"]["bending"]
    del bend["supports_x"], bend["loads_x"]
    for key, value in changes:
        bend[key] = value
    return validate_scene(raw)


def test_supports_and_loads_placed_by_their_spans():
    """The Willis test by its spans: a = 275 mm, 260 mm between the loads,
    about the middle of the 1.08 m toothed wall: the absolute positions."""
    b = _spans(("shear_span", "275 mm"), ("load_span", "260 mm")).loading.bending
    assert b.supports == pytest.approx((0.135, 0.945), abs=1e-12)
    assert b.loads == pytest.approx((0.410, 0.670), abs=1e-12)
    assert b.shear_span == pytest.approx(0.275, abs=1e-12)
    # a wall of 3 units a course (0.84 m): the same spans, centred on 0.42 m
    raw = read_scene(WILLIS)
    del raw["loading"]["bending"]["supports_x"], raw["loading"]["bending"]["loads_x"]
    raw["geometry"]["units_per_course"] = 3
    raw["loading"]["bending"].update(shear_span=0.2, load_span=0.2)
    b = validate_scene(raw).loading.bending
    assert b.supports == pytest.approx((0.12, 0.72), abs=1e-12) and b.loads == pytest.approx((0.32, 0.52))


def test_spans_in_unit_lengths_scale_with_the_brick():
    """Spans in modelled unit lengths (230 + 10 mm): 275 / 240 and 260 / 240
    place the Willis test's supports and loads; with a brick twice as long
    (and its joint) the wall and the spans are twice as long too."""
    b = _spans(("shear_span_units", 275 / 240), ("load_span_units", 260 / 240)).loading.bending
    assert b.supports == pytest.approx((0.135, 0.945), abs=1e-12)
    assert b.loads == pytest.approx((0.410, 0.670), abs=1e-12)
    raw = read_scene(WILLIS)
    bend = raw["loading"]["bending"]
    del bend["supports_x"], bend["loads_x"]
    bend.update(shear_span_units=275 / 240, load_span_units=260 / 240)
    raw["geometry"]["unit"]["length"], raw["geometry"]["joint_thickness"] = 0.470, 0.010
    b2 = validate_scene(raw).loading.bending
    assert b2.supports == pytest.approx((0.27, 1.89), abs=1e-12) and b2.shear_span == pytest.approx(0.55)


@pytest.mark.parametrize("changes,field", [
    ((("shear_span", 0.275),), "loading.bending.shear_span"),
    ((("load_span_units", 1.08),), "loading.bending.load_span_units"),
    ((("shear_span", 0.275), ("shear_span_units", 1.1), ("load_span", 0.26)), "loading.bending.shear_span_units"),
    ((("shear_span", 0.275), ("load_span", 0.26), ("loads_x", [0.41, 0.67])), "loading.bending.loads_x"),
    ((("shear_span", 0.6), ("load_span", 0.26)), "loading.bending.supports_x.0"),   # beyond the wall
])
def test_spans_refused_when_incomplete_doubled_or_too_long(changes, field):
    from masonrydem.errors import InputError
    with pytest.raises(InputError) as e:
        _spans(*changes)
    assert e.value.field == field
