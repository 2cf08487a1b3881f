"""Where a bending test's supports and loads sit, in either direction:
along the bed joints (horizontal bending, positions x) or across the
courses (vertical bending, positions z); placed by their spans or given
as positions (``placed``), and checked against the wall (``check_loading``)
before anything is built; errors name the scene's setting."""
import copy

from ..errors import InputError
from .files import set_value


SPANS = ("shear_span", "load_span")
# per direction: the global axis the wallette spans along and the suffix of
# its position settings (supports_x, loads_z, ...)
AXES = {"horizontal": (0, "x"), "vertical": (2, "z")}


# per direction: the scene's setting of the section b, and the Geometry
# property that gives it as built when not set
SECTIONS = {"horizontal": ("section_height", "built_height"), "vertical": ("section_width", "bed_length")}


def section_of(b, g, direction):
    """(the setting's key, b in m) of a bending test's section: as the
    scene sets it, else as built; the other direction's key refused."""
    key, built = SECTIONS[direction]
    for other, (okey, _) in SECTIONS.items():
        if other != direction and okey in b:
            raise InputError(f"loading.bending.{okey}", f"is the section of {other} bending, but the scene bends "
                             f"{direction}ly: give loading.bending.{key}")
    return key, b.get(key, getattr(g, built))


def vertical_defaults(schema, path=""):
    """(dotted path, value) of every setting whose default differs in
    vertical bending (the schema's default_vertical: the vertical accuracy
    study's choice, docs/accuracy.md)."""
    out = []
    for key, sub in schema.get("properties", {}).items():
        here = f"{path}.{key}" if path else key
        if isinstance(sub, dict):
            if "default_vertical" in sub:
                out.append((here, sub["default_vertical"]))
            out += vertical_defaults(sub, here)
    return tuple(out)


def fill_vertical(scene, defaults):
    """A vertical bending test's own defaults (``vertical_defaults``) where
    the scene mapping gives none, before the schema fills in the rest."""
    loading = scene.get("loading")
    if not isinstance(loading, dict) or loading.get("test", "bending") != "bending":
        return
    if not isinstance(loading.get("bending"), dict) or loading["bending"].get("direction") != "vertical":
        return
    for path, value in defaults:
        node = scene
        for key in path.split("."):
            node = node.get(key) if isinstance(node, dict) else None
        if node is None:
            set_value(scene, path, copy.deepcopy(value))


def span_of(g, direction):
    """The wall's extent along the span (m) and its modelled unit along it
    (unit length + joint; course height: unit height + joint)."""
    axis = AXES[direction][0]
    return (g.length if axis == 0 else g.height), g.modelled_unit[axis]


def placed(b, g, given, direction="horizontal"):
    """(supports, loads): positions along the span, as given, or from the
    shear span and the load span, symmetric about the middle of the span's
    direction; each span in metres (shear_span) or in modelled units along
    the span (shear_span_units: unit lengths horizontally, course heights
    vertically), so that the test scales with the brick format."""
    _, suffix = AXES[direction]
    other = next(s for d, (_, s) in AXES.items() if d != direction)
    for key in (f"supports_{other}", f"loads_{other}"):
        if key in b:
            raise InputError(f"loading.bending.{key}", f"is a position along {other}, but the scene bends "
                             f"{direction}ly (loading.bending.direction: {direction}): give "
                             f"{key[:-1]}{suffix}, or the spans")
    names = (f"supports_{suffix}", f"loads_{suffix}")
    extent, unit = span_of(g, direction)
    spans = {}
    for key in SPANS:
        if key in b and f"{key}_units" in b:
            raise InputError(f"loading.bending.{key}_units", f"is given together with loading.bending.{key}: give "
                             "the span in metres or in unit lengths, not both")
        if key in b or f"{key}_units" in b:
            spans[key] = (key, b[key]) if key in b else (f"{key}_units", b[f"{key}_units"] * unit)
    if not spans:
        missing = [k for k in names if k not in b]
        if missing:
            raise InputError(f"loading.bending.{missing[0]}", f"is required: where the test's supports and loads bear, "
                             f"as {names[0]} and {names[1]} (m), or as shear_span and load_span")
        return tuple(b[names[0]]), tuple(b[names[1]])
    if len(spans) == 1:
        (name, _), = spans.values()
        missing = (set(SPANS) - set(spans)).pop()
        raise InputError(f"loading.bending.{name}", f"needs loading.bending.{missing} (or {missing}_units) too "
                                                    "(the supports and loads are placed symmetrically from both)")
    if given:
        raise InputError(f"loading.bending.{sorted(given)[0]}", "is given together with the shear and load spans: "
                         "place the supports and loads either way, not both")
    mid, half, a = 0.5 * extent, 0.5 * spans["load_span"][1], spans["shear_span"][1]
    return (mid - half - a, mid + half + a), (mid - half, mid + half)


def check_loading(g, loading):
    """Four-point bending on the wall, the loads between the outer supports
    and no support between the loads (else the moment between the loads is
    not P a / 2, and the strength computed from it means nothing); in
    vertical bending at least two courses and a bed joint between the
    loads; a triplet of three units stacked."""
    if loading.test == "bending":
        b = loading.bending
        _, suffix = AXES[b.direction]
        extent, _ = span_of(g, b.direction)
        names = {"supports": f"supports_{suffix}", "loads": f"loads_{suffix}"}
        if b.direction == "vertical" and g.courses < 3:
            raise InputError("geometry.courses", f"vertical bending needs a wallette of at least 3 courses (its "
                             f"supports and loads lie on courses and it fails along a bed joint), got {g.courses}")
        for key, xs in (("supports", b.supports), ("loads", b.loads)):
            for i, x in enumerate(xs):
                if not (0.5 * b.strip_width <= x <= extent - 0.5 * b.strip_width):
                    raise InputError(f"loading.bending.{names[key]}.{i}", f"{x} m is outside the wall (0 to "
                                     f"{extent:.4g} m along {suffix})")
        supports, loads = b.supports, b.loads
        for i, x in enumerate(loads):
            if not min(supports) < x < max(supports):
                raise InputError(f"loading.bending.{names['loads']}.{i}", f"{x} m is not between the supports "
                                 f"(loading.bending.{names['supports']}: {min(supports)} to {max(supports)} m)")
        for i, x in enumerate(supports):
            if min(loads) <= x <= max(loads):
                raise InputError(f"loading.bending.{names['supports']}.{i}", f"{x} m lies between the loads "
                                 f"(loading.bending.{names['loads']}: {min(loads)} to {max(loads)} m); the "
                                 "supports must lie outside them")
        if b.direction == "vertical":
            _check_vertical(g, b, names)
    if loading.test == "triplet":
        for key, have, want in (("courses", g.courses, 3), ("units_per_course", g.units_per_course, 1)):
            if have != want:
                raise InputError(f"geometry.{key}", f"a triplet test has {want} (three units stacked), got {have}")


# a vertical-bending wallette's least size for its unit format: bed joints
# in the constant-moment zone, and its width in unit lengths where the
# courses lap (a lap and a whole unit, as in a wall)
MIN_BED_JOINTS = 2
MIN_WIDTH_UNITS = 1.5


def _check_vertical(g, b, names):
    """A wallette too small for its unit format to test vertical bending:
    fewer than MIN_BED_JOINTS bed joints between the loads (the test would
    measure one joint, not the masonry), or, in a bonded wall, narrower
    than MIN_WIDTH_UNITS unit lengths (its bed joints would not lap as a
    wall's do)."""
    H, L = g.modelled_unit[2], g.modelled_unit[0]
    inside = sum(min(b.loads) < k * H < max(b.loads) for k in range(1, g.courses))
    if inside < MIN_BED_JOINTS:
        raise InputError(f"loading.bending.{names['loads']}", f"{inside} bed joint(s) lie between the loads "
                         f"({min(b.loads):.4g} to {max(b.loads):.4g} m; a bed joint every {H:.4g} m): the constant "
                         f"moment must span at least {MIN_BED_JOINTS}, or the test measures one joint; space the "
                         "loads further apart or use more courses")
    x0, x1 = g.common_span
    if 0.0 < g.bond_offset < 1.0 and x1 - x0 < MIN_WIDTH_UNITS * L - 1e-12:
        raise InputError("geometry.units_per_course", f"a wallette {x1 - x0:.4g} m wide where every course "
                         f"bears is too small for its {L * 1e3:.4g} mm units in vertical bending: at least "
                         f"{MIN_WIDTH_UNITS:g} unit lengths ({MIN_WIDTH_UNITS * L:.4g} m), so that its bed joints "
                         "lap as a wall's do; add units per course, or straight ends (geometry.ends)")
