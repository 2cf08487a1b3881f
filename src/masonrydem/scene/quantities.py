"""Quantities with units, and the plausible ranges of masonry.

Wherever a scene (or a ``--set``, or a study file) gives a number, it may
give a quantity instead: "0.15 MPa", "230 mm", "0.009 N/mm", "15 GPa",
"0.6 rad".  A plain number stays SI.  The schema names each physical
field's SI unit (``unit``) and its plausible range for masonry
(``plausible: [min, max]``, ``plausible_zero: true`` where 0 is a value
on purpose, such as no precompression).  pint converts: in decimal
arithmetic, so that "0.15 MPa" gives the float 150000.0 that '0.15e6' or
'150000' give, to the last digit.  pint is imported only when a scene
holds a quantity (it takes about 0.5 s to load: a study's jobs pass plain
numbers).

A value outside its plausible range is refused, naming the field, the
value, the range and, for a plain number, the unit that brings it into the
range ("did you mean 0.15 MPa?").  A scene widens a range on purpose under
``plausible``: ``plausible: {materials.joints.ft: ["0.001 MPa", "20 MPa"]}``.
"""
import re
from decimal import Decimal
from functools import lru_cache

from ..errors import InputError

# the units a plain number most likely meant, per SI unit of a field (the
# likeliest first)
MEANT = {"Pa": ("MPa", "kPa", "GPa"), "m": ("mm", "cm", "um"), "N/m": ("N/mm",), "deg": ("rad",),
         "kg/m^3": ("t/m^3",)}


# the unit a results table reports a quantity of each SI unit in: (its text,
# its size in SI, the suffix of a column's name: f_tj_mpa, t_mm)
SHOWN = {"Pa": ("MPa", 1e6, "mpa"), "m": ("mm", 1e-3, "mm"), "N/m": ("N/mm", 1e3, "n_mm"),
         "kg/m^3": ("kg/m^3", 1.0, "kg_m3"), "deg": ("deg", 1.0, "deg"), "": ("", 1.0, "")}


def shown(unit):
    """(text, size in SI, column suffix) of the unit a results table
    reports a quantity of the SI unit ``unit`` in."""
    return SHOWN.get(unit, (unit, 1.0, unit.replace("/", "_").replace("^", "").lower()))


def column(name, unit):
    """The column of a results table that holds the input ``name`` of the
    SI unit ``unit``: the name and the unit shown, f_tj_mpa, t_mm, n."""
    suffix = shown(unit)[2]
    return f"{name}_{suffix}" if suffix else name


def to_shown(value, unit):
    """An SI value of the unit ``unit`` in the unit results show it in
    (Pa as MPa: value / 1e6, as the runs table's columns have it; m as mm:
    value * 1000)."""
    size = shown(unit)[1]
    return value / size if size >= 1 else value * round(1 / size)


@lru_cache(maxsize=None)
def registry():
    """pint's unit registry in decimal arithmetic (loaded on first use)."""
    import pint         # on first use: 0.2 s
    return pint.UnitRegistry(non_int_type=Decimal)


def to_si(value, unit, field):
    """``value`` (a number, or a text such as '0.15 MPa') as a float in the
    SI unit ``unit`` ('' dimensionless); InputError naming ``field`` when
    the text is not a quantity or has another dimension."""
    if not isinstance(value, str):
        return value
    if is_plain(value):
        return float(value)
    import pint
    ureg = registry()
    try:
        q = ureg.Quantity(quantity_text(value))
    except (pint.errors.PintError, ValueError, TypeError, AttributeError, SyntaxError):
        raise InputError(field, f"{value!r} is not a quantity (a number and a unit, such as "
                                f"'{_example(unit)}')") from None
    if not hasattr(q, "magnitude") or isinstance(q.magnitude, str):
        raise InputError(field, f"{value!r} is not a quantity")
    try:
        si = q.to(ureg.Unit(unit) if unit else ureg.dimensionless)
    except pint.errors.DimensionalityError:
        raise InputError(field, f"{value!r} reads as {q.units}, {_dimension(str(q.units))}; this setting is "
                                f"{_dimension(unit)} ({unit or 'no unit'})") from None
    return float(si.magnitude)


_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")
_SUPERSCRIPTS = str.maketrans({"\u00b2": "^2", "\u00b3": "^3", "\u00b9": "^1", "\u2074": "^4", "\u207b": "^-",
                               "\u00b7": "*", "\u22c5": "*", "\u00b5": "u", "\u03bc": "u"})


def unit_text(unit):
    """A unit as engineers write it, in the text pint reads: N/mm2 and
    N/mm\u00b2 as N/mm^2, kN/m2 as kN/m^2, kN\u00b7m as kN*m, \u00b5m as um.  A
    run of digits right after a letter is a power (no unit's symbol ends
    in a digit); what pint reads already is left as it is."""
    return re.sub(r"(?<=[A-Za-z])(\d+)", r"^\1", str(unit).translate(_SUPERSCRIPTS))


def quantity_text(value):
    """A quantity's text, '0.35 N/mm2', with its unit as pint reads it
    (``unit_text``): '0.35 N/mm^2'.  A text that is no number and unit is
    left as it is (pint then says what is wrong)."""
    m = _NUMBER.match(value)
    if not m:
        return value.strip()
    number, unit = m.groups()
    return f"{number} {unit_text(unit)}" if unit else number


WORDS = {"Pa": "a stress", "m": "a length", "N/m": "a force per length (an energy per area)",
         "kg/m^3": "a density", "deg": "an angle", "": "a ratio"}


def is_plain(value):
    """A plain number, possibly as text ('0.15', '1.5e5'): SI."""
    try:
        float(value)
        return True
    except (TypeError, ValueError):
        return False


def _dimension(unit):
    """What a unit measures, in words (else its dimensions)."""
    if unit in WORDS:
        return WORDS[unit]
    dims = registry().Unit(unit).dimensionality if unit else {}
    for si, words in WORDS.items():
        if dims == (registry().Unit(si).dimensionality if si else {}):
            return words
    return " ".join(f"{k.strip('[]')}{'' if v == 1 else f'^{v}'}" for k, v in dims.items())


def _example(unit):
    return {"Pa": "0.15 MPa", "m": "230 mm", "N/m": "0.009 N/mm", "deg": "35 deg", "kg/m^3": "1.9 t/m^3"}.get(unit, "0.4")


def _nodes(value, schema, path):
    """(dotted path, value, schema, setter) for every number the schema
    types, under ``value`` (as read from YAML, not yet validated)."""
    if not isinstance(schema, dict):
        return
    if isinstance(value, dict) and "properties" in schema:
        for key, sub in schema["properties"].items():
            if key in value:
                sub_path = f"{path}.{key}" if path else key
                if _is_number(sub):
                    yield sub_path, value[key], sub, _setter(value, key)
                else:
                    yield from _nodes(value[key], sub, sub_path)
    elif isinstance(value, list) and isinstance(schema.get("items"), dict):
        items = schema["items"]
        for i, v in enumerate(value):
            if _is_number(items):
                yield f"{path}.{i}", v, items, _setter(value, i)
            else:
                yield from _nodes(v, items, f"{path}.{i}")


def _is_number(schema):
    return schema.get("type") == "number"


def _setter(container, key):
    def put(v):
        container[key] = v
    return put


def convert(scene, schema):
    """Replaces, in place, every quantity of ``scene`` where the schema wants
    a number by its SI float (plain numbers are left as they are); returns
    {dotted path: the quantity as written}."""
    written = {}
    for path, value, sub, put in list(_nodes(scene, schema, "")):
        if isinstance(value, str):
            put(to_si(value, sub.get("unit", ""), path))
            if not is_plain(value):
                written[path] = value
    return written


def widened(scene, schema):
    """The scene's own ranges (its 'plausible' section: a field's dotted path
    without list indices, and [min, max], quantities or SI numbers), in SI."""
    own = scene.get("plausible") or {}
    if not isinstance(own, dict):
        raise InputError("plausible", "must be a mapping of settings to [min, max], e.g. "
                                      "plausible: {materials.joints.ft: ['0.001 MPa', '20 MPa']}")
    out = {}
    for key, bounds in own.items():
        sub = schema_at(schema, str(key))
        if sub is None or "plausible" not in sub:
            raise InputError(f"plausible.{key}", "is not a setting with a plausible range (a dotted path such "
                                                 "as materials.joints.ft)")
        if not isinstance(bounds, list) or len(bounds) != 2:
            raise InputError(f"plausible.{key}", f"must be [min, max], got {bounds!r}")
        lo, hi = (to_si(b, sub.get("unit", ""), f"plausible.{key}.{i}") for i, b in enumerate(bounds))
        if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in (lo, hi)) or not lo <= hi:
            raise InputError(f"plausible.{key}", f"must be [min, max] with min <= max, got {bounds!r}")
        out[key] = (lo, hi)
    return out


def schema_at(schema, dotted):
    """The schema of the number field at a dotted path (list items skipped)."""
    node = schema
    for key in dotted.split("."):
        node = node.get("properties", {}).get(key) if isinstance(node, dict) else None
        if isinstance(node, dict) and node.get("type") == "array":
            node = node.get("items")
    return node if isinstance(node, dict) and _is_number(node) else None


def check_plausible(scene, schema, written=None):
    """Refuses the first value outside its field's plausible range (the
    schema's, or the scene's own under 'plausible'); ``written``: the
    quantities as the scene wrote them (convert), which are shown as such
    (a plain number, in SI, also gets the unit it most likely meant)."""
    written = written or {}
    own = widened(scene, schema)
    for path, value, sub, _ in _nodes(scene, schema, ""):
        if "plausible" not in sub or not isinstance(value, (int, float)) or isinstance(value, bool):
            continue
        general = ".".join(p for p in path.split(".") if not p.isdigit())
        lo, hi = own.get(general, sub["plausible"])
        if lo <= value <= hi or (value == 0 and sub.get("plausible_zero")):
            continue
        unit = sub.get("unit", "")
        raise InputError(path, _refusal(value, unit, (lo, hi, sub.get("plausible_zero")), general,
                                        written.get(path)))


def _refusal(value, unit, span, general, written):
    lo, hi, zero = span
    shown = repr(written) if written else f"{value:g} {unit}".rstrip()
    text = (f"{shown} is outside the plausible range for masonry, "
            f"{'0, or ' if zero else ''}{_show(lo, unit)} to {_show(hi, unit)}")
    guess = None if written else meant(value, unit, lo, hi)
    if guess:
        text += f": did you mean {guess}? (a plain number is SI: write its unit, e.g. '{guess}')"
    return text + f"; to go beyond on purpose, widen it in the scene: plausible: {{{general}: [min, max]}}"


def _show(x, unit):
    """``x`` (SI) in the unit of MEANT that writes it between 1 and 1000."""
    for candidate in (unit, *MEANT.get(unit, ())):
        y = _convert(x, unit, candidate) if candidate != unit else x
        if 1 <= abs(y) < 1000:
            return f"{y:g} {candidate}".rstrip()
    return f"{x:g} {unit}".rstrip()


def _convert(x, unit, to):
    """The number ``x`` in ``unit`` as a float in ``to`` (decimal arithmetic)."""
    return float(registry().Quantity(Decimal(repr(float(x))), unit).to(to).magnitude)


def meant(value, unit, lo, hi):
    """The first unit of MEANT[unit] that brings the plain ``value`` into the
    range, written as a quantity; None if none does."""
    for candidate in MEANT.get(unit, ()):
        x = _convert(value, candidate, unit)
        if lo <= x <= hi:
            return f"{value:g} {candidate}"
    return None
