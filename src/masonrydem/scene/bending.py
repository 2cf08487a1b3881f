"""Where a test's supports and loads sit: placed by their spans or given
as positions (``placed``), and checked against the wall (``check_loading``)
before anything is built; errors name the scene's setting."""
from ..errors import InputError


SPANS = ("shear_span", "load_span")


def placed(b, g, given):
    """(supports_x, loads_x): as given, or from the shear span and the load
    span, symmetric about the wall's middle; each span in metres
    (shear_span) or in modelled unit lengths, brick plus joint
    (shear_span_units), so that the test scales with the brick format."""
    spans = {}
    for key in SPANS:
        if key in b and f"{key}_units" in b:
            raise InputError(f"loading.bending.{key}_units", f"is given together with loading.bending.{key}: give "
                             "the span in metres or in unit lengths, not both")
        if key in b or f"{key}_units" in b:
            spans[key] = (key, b[key]) if key in b else (f"{key}_units", b[f"{key}_units"] * g.modelled_unit[0])
    if not spans:
        missing = [k for k in ("supports_x", "loads_x") if k not in b]
        if missing:
            raise InputError(f"loading.bending.{missing[0]}", "is required: where the test's supports and loads bear, "
                             "as supports_x and loads_x (m), or as shear_span and load_span")
        return tuple(b["supports_x"]), tuple(b["loads_x"])
    if len(spans) == 1:
        (name, _), = spans.values()
        missing = (set(SPANS) - set(spans)).pop()
        raise InputError(f"loading.bending.{name}", f"needs loading.bending.{missing} (or {missing}_units) too "
                                                    "(the supports and loads are placed symmetrically from both)")
    if given:
        raise InputError(f"loading.bending.{sorted(given)[0]}", "is given together with the shear and load spans: "
                         "place the supports and loads either way, not both")
    mid, half, a = 0.5 * g.length, 0.5 * spans["load_span"][1], spans["shear_span"][1]
    return (mid - half - a, mid + half + a), (mid - half, mid + half)


def check_loading(g, loading):
    """Four-point bending on the wall, the loads between the outer supports
    and no support between the loads (else the moment between the loads is
    not P a / 2, and the strength computed from it means nothing); a
    triplet of three units stacked."""
    if loading.test == "bending":
        b = loading.bending
        for key, xs in (("supports_x", b.supports_x), ("loads_x", b.loads_x)):
            for i, x in enumerate(xs):
                if not (0.5 * b.strip_width <= x <= g.length - 0.5 * b.strip_width):
                    raise InputError(f"loading.bending.{key}.{i}", f"{x} m is outside the wall (0 to {g.length:.4g} m)")
        supports, loads = b.supports_x, b.loads_x
        for i, x in enumerate(loads):
            if not min(supports) < x < max(supports):
                raise InputError(f"loading.bending.loads_x.{i}", f"{x} m is not between the supports "
                                 f"(loading.bending.supports_x: {min(supports)} to {max(supports)} m)")
        for i, x in enumerate(supports):
            if min(loads) <= x <= max(loads):
                raise InputError(f"loading.bending.supports_x.{i}", f"{x} m lies between the loads "
                                 f"(loading.bending.loads_x: {min(loads)} to {max(loads)} m); the supports must "
                                 "lie outside them")
    if loading.test == "triplet":
        for key, have, want in (("courses", g.courses, 3), ("units_per_course", g.units_per_course, 1)):
            if have != want:
                raise InputError(f"geometry.{key}", f"a triplet test has {want} (three units stacked), got {have}")
