"""A lab's test results read from a CSV sheet, refused before any fit when
something is wrong, and turned into the model's parameter
(docs/lab-to-design.md, sections 1 to 3).

Three forms, told apart by their headers; every header but the text
columns (``failure``, ``specimen``, ``note``) is ``name [unit]``:

1. results: one column of strengths (or moduli), ``f_tj [MPa]``;
2. bond wrench: ``load``, ``lever arm``, ``width`` (the bed's length along
   the unit), ``depth`` (the joint's depth in the plane of bending: the wall's
   thickness), optional ``wrench weight`` with ``wrench lever arm``, and
   ``unit weight`` (what the joint carries at its centre);
3. unit flexure: ``load``, ``span``, optional ``load span`` (four-point
   bending; without it three-point), ``width``, ``depth``;
4. wallette (EN 1052-2): ``load``, ``support span``, ``load span``,
   ``width``, ``thickness``, optional ``precompression``, and a text column
   ``direction``: vertical (or parallel: the plane of failure parallel to
   the bed joints, f_x1) or horizontal (perpendicular: f_x2), each row's
   own.  Wallette tests are not fitted: they are set beside a study's
   prediction for their direction and level (analysis/directions.py).

A sheet of the second or third form may carry one more column in a stress
unit, of any name: the strengths the lab computed from its loads.  Each is
checked against the strength the loads give here, within LAB_TOLERANCE and
the rounding of the digits written; the loads' strengths are the ones used.

Rows are numbered as a text editor shows the file's lines (comment lines,
starting with '#', and the header count), columns as the header writes
them: ``lab.csv row 4, column 'load [kN]'``.
"""
import csv
import hashlib
import io
import math
import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..scene import to_si

MIN_RESULTS = 3
LAB_TOLERANCE = 0.01     # a lab's computed strength agrees with the loads' within 1 %, and its rounding
METHODS = {"results": "read as written", "wallette": "EN 1052-2 four-point bending, 3 F (l1 - l2) / (2 b t^2)",
           "bond_wrench": "bond wrench: (F1 e1 + F2 e2) / Z - (F1 + F2 + F3) / A, lever arms from the joint's centre",
           "unit_flexure": "three-point bending, 3 P L / (2 b d^2)"}
TEXT_COLUMNS = ("failure", "specimen", "note", "direction")
# a wallette test's direction as a sheet may write it -> the bending direction
DIRECTIONS = {"vertical": "vertical", "parallel": "vertical", "horizontal": "horizontal",
              "perpendicular": "horizontal"}

# the failure column's codes per test: kept, or screened with the reason the
# report gives; an empty cell keeps the specimen, any other text is refused
TEST_CODES = {
    "bond_wrench": {"keep": ("", "ok", "valid", "bond", "joint"),
                    "screen": {"unit": "broke through a unit: it measured the unit, not the bond",
                               "outside": "failed outside the tested joint",
                               "clamp": "failed at, or because of, the clamp",
                               "invalid": "declared invalid by the lab"}},
    "unit_flexure": {"keep": ("", "ok", "valid", "inside"),
                     "screen": {"outside": "broke outside the constant-moment zone",
                                "support": "broke at a support or under a loading point",
                                "invalid": "declared invalid by the lab"}},
    "wallette": {"keep": ("", "ok", "valid", "joint", "bed joint", "stepped", "unit", "inside"),
                 "screen": {"outside": "broke outside the constant-moment zone",
                            "support": "broke at a support or under a loading point",
                            "invalid": "declared invalid by the lab"}},
}
# a results column, whose sheet does not say which test it holds, takes every
# test's codes; its own reasons where they differ
RESULTS_SCREEN = {"invalid": "declared invalid by the lab", "outside": "failed outside what the test measures"}
FAILURE_CODES = {
    "results": {"keep": tuple(dict.fromkeys(c for f in TEST_CODES.values() for c in f["keep"])),
                "screen": {**{c: r for f in TEST_CODES.values() for c, r in f["screen"].items()}, **RESULTS_SCREEN}},
    **TEST_CODES,
}

# header names (lower case) -> the formula's symbol, per form; symbol -> SI unit, words
BOND_WRENCH = {"load": "F1", "lever arm": "e1", "wrench weight": "F2", "wrench lever arm": "e2",
               "unit weight": "F3", "width": "b", "depth": "d"}
UNIT_FLEXURE = {"load": "P", "span": "L", "load span": "L_i", "width": "b", "depth": "d"}
WALLETTE = {"load": "F", "support span": "l1", "load span": "l2", "width": "b", "thickness": "t",
            "precompression": "sigma_d"}
# a sheet's form by the column that tells it (the first found)
FORMS = (("support span", WALLETTE, "wallette"), ("span", UNIT_FLEXURE, "unit_flexure"),
         ("lever arm", BOND_WRENCH, "bond_wrench"))
SYMBOLS = {"F1": ("N", "the failure load"), "F2": ("N", "the wrench's weight"), "F3": ("N", "the unit's weight"),
           "P": ("N", "the failure load"), "e1": ("m", "the lever arm"), "e2": ("m", "the wrench's lever arm"),
           "L": ("m", "the span"), "L_i": ("m", "the load span"), "b": ("m", "the width"), "d": ("m", "the depth"),
           "lab": ("Pa", "the lab's computed strength"), "F": ("N", "the failure load"),
           "l1": ("m", "the support span"), "l2": ("m", "the load span"), "t": ("m", "the thickness"),
           "sigma_d": ("Pa", "the precompression")}
OPTIONAL = ("F2", "e2", "F3", "L_i", "sigma_d")
MEASURES = {"bond_wrench": "flexural_bond", "unit_flexure": "modulus_of_rupture"}


def bond_wrench_strength(F1, e1, b, d, F2=0.0, e2=0.0, F3=0.0):
    """Flexural bond strength of a joint broken by a bond wrench (SI):
    the elastic stress at the face that opens, bending less the vertical
    loads' compression, f = (F1 e1 + F2 e2) / Z - (F1 + F2 + F3) / A,
    Z = b d^2 / 6, A = b d, the lever arms measured from the joint's centre
    (ASTM C1072's gross-area expression, with F3 the weight the joint
    carries)."""
    Z, A = b * d ** 2 / 6.0, b * d
    return (F1 * e1 + F2 * e2) / Z - (F1 + F2 + F3) / A


def flexural_strength(P, L, b, d, L_i=0.0):
    """Modulus of rupture of a simply supported unit (SI): the moment
    between the loads P (L - L_i) / 4 over Z = b d^2 / 6, f = 3 P (L - L_i) /
    (2 b d^2); L_i = 0 is three-point bending (3 P L / 2 b d^2), L_i = L / 3
    third-point bending (P L / b d^2)."""
    return 3.0 * P * (L - L_i) / (2.0 * b * d ** 2)


def wallette_strength(F, l1, l2, b, t):
    """A wallette's flexural strength in four-point bending (EN 1052-2,
    SI): the moment between the loads F (l1 - l2) / 4 over Z = b t^2 / 6,
    f_x = 3 F (l1 - l2) / (2 b t^2)."""
    return 3.0 * F * (l1 - l2) / (2.0 * b * t ** 2)


def read_sheet(path, unit="Pa"):
    """The sheet at ``path`` read, every cell checked: a dict with the
    file's name, sha256, form, quantity, what it measured (flexural_bond,
    modulus_of_rupture, or None for a results column), the valid results
    in SI (``values``, the results column's in ``unit``), their rows, the
    specimens' mean depth (m, None for results), the screened specimens
    (row, code, reason) and the method.  InputError names the row and the
    column: no header or rows, a header without a unit or of an unknown
    name, a cell that is no finite number, a zero or negative load,
    dimension or result, an unknown failure code, every specimen
    screened, fewer than 3 results."""
    path = Path(path)
    raw = path.read_bytes()
    lines = [(i, t) for i, t in enumerate(raw.decode("utf-8-sig").splitlines(), 1)
             if t.strip() and not t.lstrip().startswith("#")]
    if not lines:
        raise InputError(path.name, "the file has no header and no specimens")
    header_row, rows = lines[0][0], lines[1:]
    sep = _separator(lines[0][1])
    table = [[c.strip() for c in next(csv.reader(io.StringIO(t), delimiter=sep))] for _, t in lines]
    columns = table[0]
    where = lambda row, col: f"{path.name} row {row}, column '{col}'"   # noqa: E731
    if not rows:
        raise InputError(f"{path.name} row {header_row}", "a header and no specimens under it")
    form, keys, text = _columns(columns, header_row, where)
    factors = {c: _unit_factor(c, SYMBOLS[k][0] if form != "results" else unit, where(header_row, c))
               for c, k in keys.items()}
    cells, screened = [], []
    for (row, _), cells_of_row in zip(rows, table[1:]):
        if len(cells_of_row) != len(columns):
            raise InputError(f"{path.name} row {row}", f"{len(cells_of_row)} cells under {len(columns)} columns")
        record = dict(zip(columns, cells_of_row))
        code = record[text["failure"]].lower() if "failure" in text else ""
        if code in FAILURE_CODES[form]["screen"]:
            screened.append({"row": row, "failure": record[text["failure"]],
                             "reason": FAILURE_CODES[form]["screen"][code]})
            continue
        if code not in FAILURE_CODES[form]["keep"]:
            codes = FAILURE_CODES[form]
            raise InputError(where(row, text["failure"]),
                             f"{record[text['failure']]!r} is no failure code of a {form.replace('_', ' ')} sheet: "
                             f"kept {', '.join(c for c in codes['keep'] if c)} (or empty), screened "
                             f"{', '.join(codes['screen'])}")
        cell = {k: _cell(record[c], factors[c], k, where(row, c)) for c, k in keys.items()}
        if form == "wallette":
            said = record[text["direction"]].strip().lower()
            if said not in DIRECTIONS:
                raise InputError(where(row, text["direction"]), f"{record[text['direction']]!r} is no direction: "
                                 "vertical (or parallel: the plane of failure parallel to the bed joints) or "
                                 "horizontal (or perpendicular)")
            cell["direction"] = DIRECTIONS[said]
        lab = next((c for c, k in keys.items() if k == "lab"), None)
        if lab:                                # half a unit of the last digit written
            cell["lab_rounding"] = 0.5 * 10.0 ** -len(record[lab].partition(".")[2]) * factors[lab]
        cells.append((row, cell))
    return _results(path, raw, form, keys, cells, screened, where, text, header_row)


def _separator(header):
    try:
        return csv.Sniffer().sniff(header, delimiters=",;\t").delimiter
    except csv.Error:
        return ","


def _columns(columns, row, where):
    """(form, {column: symbol}, {text column's name: column})."""
    text, named = {}, {}
    for col in columns:
        m = re.fullmatch(r"(.*?)\s*\[\s*(.*?)\s*\]", col)
        if m is None:
            if col.lower() in TEXT_COLUMNS:
                text[col.lower()] = col
                continue
            raise InputError(where(row, col), "a header needs its unit, 'name [unit]', such as 'load [kN]' or "
                                              "'f_tj [MPa]' (the text columns: failure, specimen, note)")
        if not m[1] or not m[2]:
            raise InputError(where(row, col), "a header is a name and a unit, 'name [unit]'")
        named[col] = m[1].strip().lower()
    if not named:
        raise InputError(where(row, columns[0]), "no column of results")
    names = set(named.values())
    form, vocabulary = next(((f, v) for column, v, f in FORMS if column in names), (None, None))
    if vocabulary is None:
        if len(named) == 1:
            return "results", {col: "result" for col in named}, text
        raise InputError(where(row, list(named)[1]), "one column of results ('f_tj [MPa]'), a bond-wrench sheet "
                                                     "(a 'lever arm' column), a flexural-test sheet (a 'span' "
                                                     "column) or a wallette sheet (a 'support span' column)")
    if form == "wallette" and "direction" not in text:
        raise InputError(where(row, columns[0]), "a wallette sheet states each test's direction: add a column "
                                                 "'direction', vertical (the plane of failure parallel to the bed "
                                                 "joints, f_x1) or horizontal (perpendicular to them, f_x2)")
    keys = {}
    for col, name in named.items():
        if name not in vocabulary and "lab" not in keys.values() and _is_stress(col):
            keys[col] = "lab"                  # the strength the lab computed from the loads: checked against them
            continue
        if name not in vocabulary or vocabulary[name] in keys.values():
            raise InputError(where(row, col), f"no column of a {form.replace('_', ' ')} sheet, or a second one of "
                                              f"its name (its columns: {', '.join(vocabulary)}, and one of the "
                                              "strengths the lab computed, in a stress unit)")
        keys[col] = vocabulary[name]
    missing = [n for n, k in vocabulary.items() if k not in keys.values() and k not in OPTIONAL]
    if missing:
        raise InputError(where(row, list(named)[0]), f"a {form.replace('_', ' ')} sheet needs the columns "
                                                     f"{', '.join(missing)} too")
    if form == "bond_wrench" and ("F2" in keys.values()) != ("e2" in keys.values()):
        raise InputError(where(row, list(named)[0]), "the wrench's weight and its lever arm go together: both or neither")
    return form, keys, text


def _is_stress(col):
    """Whether a header's unit is a stress's."""
    try:
        _unit_factor(col, "Pa", col)
    except InputError:
        return False
    return True


def _unit_factor(col, si, field):
    """The size in SI of one of the column's unit, of the dimension ``si``."""
    unit = re.fullmatch(r".*\[\s*(.*?)\s*\]", col)[1]
    return to_si(f"1 {unit}", si, field)


def _cell(text, factor, symbol, field):
    """A cell's number in SI: refused if empty, not a finite number, or
    (a result, a load or a dimension) not above zero."""
    try:
        value = float(text)
    except ValueError:
        comma = " (a decimal comma? write 0.28, not 0,28)" if re.fullmatch(r"-?\d+,\d+", text) else ""
        raise InputError(field, f"{text!r} is not a number{comma}" if text else "the cell is empty") from None
    if not math.isfinite(value):
        raise InputError(field, f"{text!r} is not a finite number")
    if value < 0 or value == 0 and symbol not in OPTIONAL:
        raise InputError(field, f"{text}: {SYMBOLS.get(symbol, ('', 'a result'))[1]} must be above 0")
    return value * factor


def _results(path, raw, form, keys, cells, screened, where, text, header_row):
    result_col = next(c for c, k in keys.items() if k in ("result", "F1", "P", "F"))
    if not cells:
        raise InputError(f"{path.name} rows {screened[0]['row']}-{screened[-1]['row']}, column '{text['failure']}'",
                         "every specimen is screened out: nothing is left to fit")
    values = []
    method = "four-point bending, 3 P (L - L_i) / (2 b d^2)" if "L_i" in keys.values() else METHODS[form]
    for row, c in cells:
        if form == "results":
            v = c["result"]
        elif form == "wallette":
            if c["l2"] >= c["l1"]:
                raise InputError(where(row, next(k for k, s in keys.items() if s == "l2")),
                                 "the load span must be shorter than the support span")
            v = wallette_strength(c["F"], c["l1"], c["l2"], c["b"], c["t"])
        elif form == "bond_wrench":
            v = bond_wrench_strength(c["F1"], c["e1"], c["b"], c["d"], c.get("F2", 0.0), c.get("e2", 0.0),
                                     c.get("F3", 0.0))
        else:
            if c.get("L_i", 0.0) >= c["L"]:
                raise InputError(where(row, next(k for k, s in keys.items() if s == "L_i")),
                                 "the load span must be shorter than the span")
            v = flexural_strength(c["P"], c["L"], c["b"], c["d"], c.get("L_i", 0.0))
        if "lab" in c and abs(c["lab"] - v) > LAB_TOLERANCE * v + c["lab_rounding"]:
            raise InputError(where(row, next(k for k, s in keys.items() if s == "lab")),
                             f"the lab's {c['lab'] / 1e6:.4g} MPa, where the loads give {v / 1e6:.4g} MPa "
                             f"by {method}: another formula (the lever arms, the unit's weight?) or a "
                             "wrong cell")
        if not v > 0:
            raise InputError(where(row, result_col), f"the strength comes out at {v / 1e6:.4g} MPa: the vertical "
                                                     "loads' compression exceeds the bending (lever arms from the "
                                                     "joint's centre?)")
        values.append(v)
    if len(values) < MIN_RESULTS:
        rows = ", ".join(str(r) for r, _ in cells)
        raise InputError(f"{path.name} row{'s' if len(cells) > 1 else ''} {rows}, column '{result_col}'",
                         f"{len(values)} valid result{'s' if len(values) > 1 else ''}: at least {MIN_RESULTS} "
                         "are needed" + (f" ({len(screened)} screened out)" if screened else ""))
    quantity = re.match(r"(.*?)\s*\[", result_col)[1] if form == "results" else \
        {"bond_wrench": "flexural bond strength", "unit_flexure": "modulus of rupture",
         "wallette": "flexural strength"}[form]
    if "lab" in keys.values():
        method += f"; the lab's column '{next(k for k, s in keys.items() if s == 'lab')}' agrees with it"
    depth = float(np.mean([c["d"] for _, c in cells])) if form in ("bond_wrench", "unit_flexure") else None
    per_test = {"directions": [c["direction"] for _, c in cells],
                "levels": np.array([c.get("sigma_d", 0.0) for _, c in cells])} if form == "wallette" else {}
    return {**per_test, "name": path.name, "path": str(path), "sha256": hashlib.sha256(raw).hexdigest(), "form": form,
            "quantity": quantity, "measured": MEASURES.get(form), "values": np.array(values),
            "rows": [r for r, _ in cells], "depth": depth, "screened": screened, "method": method,
            "header_row": header_row}


# --- from the test to the model's parameter -------------------------------------
CONVERSIONS = {
    "flexural_bond": "EN 1992-1-1:2004, 3.1.8(1), eq. (3.23), f_ctm,fl = max(1.6 - h/1000, 1) f_ctm (h in mm), "
                     "at the joint's depth: a relation of concrete's flexural and axial tensile strengths, taken "
                     "by analogy for the joint's bond (no masonry source relating the bond wrench to direct "
                     "tension was found)",
    "modulus_of_rupture": "EN 1992-1-1:2004, 3.1.8(1), eq. (3.23), f_ctm,fl = max(1.6 - h/1000, 1) f_ctm (h in mm), "
                          "at the unit's depth: a relation of concrete's flexural and axial tensile strengths, "
                          "taken by analogy for a fired-clay unit",
    "as_is": "none: the column holds the model's quantity itself (a direct tension test, a modulus)",
}


def conversion(measured, depth=None, factor=None, source=None):
    """(factor, source): the model's parameter is ``factor`` times what the
    test measured.  By default the flexural tests by EN 1992-1-1's relation
    at ``depth`` (m), 1 / max(1.6 - h/1000, 1); ``as_is`` 1.  A ``factor``
    given by hand needs its ``source``."""
    if measured not in CONVERSIONS:
        raise InputError("--measured", f"{measured!r}: say what the results measured: {', '.join(CONVERSIONS)}")
    if factor is not None:
        if not factor > 0 or not source:
            raise InputError("--factor", f"{factor}: a factor above 0, with its --source")
        return float(factor), source
    if measured == "as_is":
        return 1.0, CONVERSIONS[measured]
    if depth is None or not depth > 0:
        raise InputError("--depth", f"the {measured.replace('_', ' ')} converts at the specimen's depth: give it "
                                    "(such as --depth '100 mm')")
    return 1.0 / max(1.6 - depth * 1e3 / 1000.0, 1.0), CONVERSIONS[measured]


def wallette_summary(lab):
    """The lines ``fit`` prints for a wallette sheet: its tests per
    direction and precompression (count, mean, range), and where they go
    (beside a study's prediction: they are not fitted)."""
    lines = [f"{lab['name']}: {len(lab['values'])} wallette tests ({lab['method']})"]
    if lab["screened"]:
        lines += [f"screened: row {r['row']} ({r['failure']}): {r['reason']}" for r in lab["screened"]]
    keys = sorted(set(zip(lab["directions"], lab["levels"])))
    for direction, level in keys:
        x = np.array([v for d, lv, v in zip(lab["directions"], lab["levels"], lab["values"])
                      if (d, lv) == (direction, level)]) / 1e6
        name = "f_x1, plane of failure parallel to the bed joints" if direction == "vertical" else \
            "f_x2, plane of failure perpendicular to the bed joints"
        lines.append(f"{direction} bending ({name}) at {level / 1e6:g} MPa precompression: {x.size} tests, mean "
                     f"{x.mean():.4g} MPa, {x.min():.4g} to {x.max():.4g} MPa")
    lines.append("wallette tests are set beside a study's prediction, not fitted: name the sheet as the workflow "
                 "config's directions: wallettes (docs/lab-to-design.md, 11)")
    return lines
