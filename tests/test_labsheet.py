"""A lab's sheet read (analysis/labsheet.py), each check against an
independent reason: the committed sheets read a second time with the csv
module and worked again, the bond wrench's stress by the equilibrium of the
joint's section, the flexural test by statics, the failure codes as
docs/lab-to-design.md (section 1) lists them, and EN 1992-1-1's relation
at depths worked by hand.  tests/test_labfit.py has the specimens worked by
hand and the refusals."""
import csv

import numpy as np
import pytest

from masonrydem.analysis import labsheet as S
from masonrydem.errors import InputError

BOND_SHEET, UNIT_SHEET = "config/lab/waal_bond_wrench.csv", "config/lab/waal_unit_flexure.csv"
SI = {"N": 1.0, "kN": 1e3, "mm": 1e-3}            # the sheets' units in N and m, by hand


def _second_reading(path):
    """(line, cells by header) of every specimen: the line as a text editor
    numbers it, comments and header counted."""
    body = [(i, t) for i, t in enumerate(open(path).read().splitlines(), 1) if t.strip() and not t.startswith("#")]
    header = next(csv.reader([body[0][1]]))
    return [(i, dict(zip(header, next(csv.reader([t]))))) for i, t in body[1:]]


def _si(record, name):
    """The cell of the column 'name [unit]' in N or m."""
    (col,) = [c for c in record if c.split(" [")[0] == name]
    return float(record[col]) * SI[col.split("[")[1].rstrip("]")]


def _section_stress(N, M, b, d):
    """The joint's stress at the face that opens, by equilibrium alone: the
    linear stress a + c y over the section (y from its centre, b wide, d
    deep) whose resultant is N (tension positive) and whose moment about
    the centre is M, the two integrals by Gauss-Legendre, solved for a and
    c; then a + c d / 2."""
    y, w = np.polynomial.legendre.leggauss(4)
    y, w = y * d / 2, w * b * d / 2
    a, c = np.linalg.solve([[w.sum(), (w * y).sum()], [(w * y).sum(), (w * y * y).sum()]], [N, M])
    return a + c * d / 2


def _midspan_moment_stress(loads, span, b, d):
    """Statics of a simply supported span: the left reaction by moments
    about the right support, the moment at midspan of the left part's free
    body, over the elastic section modulus b d^2 / 6."""
    ra = sum(f * (span - x) for f, x in loads) / span
    return (ra * span / 2 - sum(f * (span / 2 - x) for f, x in loads if x < span / 2)) / (b * d * d / 6)


def test_bond_wrench_by_the_equilibrium_of_the_joints_section():
    """Random specimens (seeded): the bending of the load and the wrench
    about the joint's centre, the compression of the load, the wrench and
    the unit above, to 1e-9; a specimen without wrench columns takes F2 =
    F3 = 0."""
    g = np.random.default_rng(41)
    for _ in range(50):
        F1, F2, F3 = g.uniform(100, 900), g.uniform(0, 80), g.uniform(0, 40)
        e1, e2, b, d = g.uniform(0.2, 0.4), g.uniform(0.05, 0.2), g.uniform(0.09, 0.25), g.uniform(0.08, 0.2)
        assert S.bond_wrench_strength(F1, e1, b, d, F2, e2, F3) == pytest.approx(
            _section_stress(-(F1 + F2 + F3), F1 * e1 + F2 * e2, b, d), rel=1e-9)
        assert S.bond_wrench_strength(F1, e1, b, d) == pytest.approx(_section_stress(-F1, F1 * e1, b, d), rel=1e-9)


def test_every_row_of_the_committed_sheets_read_again():
    """Both committed sheets read with the csv module and the units by hand
    (kN, mm): every kept specimen's strength by the section's equilibrium
    (bond wrench) or statics (three-point, the load at midspan), to 1e-9;
    the rows kept and screened, with their codes as written, and the mean
    depth that the conversion takes."""
    bond, rows = S.read_sheet(BOND_SHEET), _second_reading(BOND_SHEET)
    kept = [(i, r) for i, r in rows if r["failure"] not in ("unit", "outside", "clamp", "invalid")]
    assert bond["rows"] == [i for i, _ in kept] and len(kept) == 10
    assert [(s["row"], s["failure"]) for s in bond["screened"]] == [(i, r["failure"]) for i, r in rows
                                                                    if (i, r) not in kept] == [(14, "unit")]
    expected = [_section_stress(-(_si(r, "load") + _si(r, "wrench weight") + _si(r, "unit weight")),
                                _si(r, "load") * _si(r, "lever arm") + _si(r, "wrench weight") * _si(r, "wrench lever arm"),
                                _si(r, "width"), _si(r, "depth")) for _, r in kept]
    assert list(bond["values"]) == pytest.approx(expected, rel=1e-9)
    assert bond["depth"] == pytest.approx(np.mean([_si(r, "depth") for _, r in kept]), rel=1e-12)
    units, rows = S.read_sheet(UNIT_SHEET), _second_reading(UNIT_SHEET)
    kept = [(i, r) for i, r in rows if r["failure"] not in ("outside", "support", "invalid")]
    assert units["rows"] == [i for i, _ in kept] and [s["row"] for s in units["screened"]] == [11]
    expected = [_midspan_moment_stress([(_si(r, "load"), _si(r, "span") / 2)], _si(r, "span"), _si(r, "width"),
                                       _si(r, "depth")) for _, r in kept]
    assert list(units["values"]) == pytest.approx(expected, rel=1e-9)
    assert units["depth"] == pytest.approx(0.050, rel=1e-12) and units["form"] == "unit_flexure"


FOUR = "specimen,load [kN],span [mm],load span [mm],width [mm],depth [mm],failure\n"


def test_a_four_point_sheet_by_statics(tmp_path):
    """Two loads P/2 at (L -+ L_i)/2: the midspan moment by statics, to
    1e-9; third-point loading (L_i = L/3) is P L / (b d^2); a load span as
    long as the span, or longer, is refused naming its row and column."""
    p = tmp_path / "four.csv"
    p.write_text(FOUR + "F1,6.0,180,60,100,50,inside\nF2,5.5,180,100,100,50,ok\nF3,6.2,200,40,90,55,\n")
    lab = S.read_sheet(p)
    expected = [_midspan_moment_stress([(P / 2, (L - Li) / 2), (P / 2, (L + Li) / 2)], L, b, d) for P, L, Li, b, d in
                ((6e3, 0.18, 0.06, 0.1, 0.05), (5.5e3, 0.18, 0.1, 0.1, 0.05), (6.2e3, 0.2, 0.04, 0.09, 0.055))]
    assert list(lab["values"]) == pytest.approx(expected, rel=1e-9) and "four-point" in lab["method"]
    assert lab["values"][0] == pytest.approx(6e3 * 0.18 / (0.1 * 0.05 ** 2), rel=1e-12)
    for span in ("180", "190"):
        p.write_text(FOUR + f"F1,6.0,180,60,100,50,\nF2,5.5,180,{span},100,50,\nF3,6.2,200,40,90,55,\n")
        with pytest.raises(InputError) as e:
            S.read_sheet(p)
        assert e.value.field == "four.csv row 3, column 'load span [mm]'"


# the failure codes per sheet as docs/lab-to-design.md, section 1, lists them: kept, screened
CODES = {
    "f_tj [MPa],failure\n": (("ok", "valid", "bond", "joint", "inside"), ("unit", "outside", "clamp", "support",
                                                                          "invalid"), "0.3"),
    "load [N],lever arm [mm],width [mm],depth [mm],failure\n":
        (("ok", "valid", "bond", "joint"), ("unit", "outside", "clamp", "invalid"), "500,300,210,100"),
    "load [kN],span [mm],width [mm],depth [mm],failure\n":
        (("ok", "valid", "inside"), ("outside", "support", "invalid"), "4.0,180,100,50"),
}


@pytest.mark.parametrize("head", list(CODES), ids=["results", "bond wrench", "unit flexure"])
def test_failure_codes_as_the_docs_list_them(tmp_path, head):
    """Every code the docs keep is kept (any case, and an empty cell),
    every code they screen is screened with its row and the code as
    written, and any other is refused naming its row."""
    keep, screen, cells = CODES[head]
    codes = ["", *keep, *(c.upper() for c in keep), *screen, *(c.title() for c in screen)]
    p = tmp_path / "lab.csv"
    p.write_text(head + "".join(f"{cells},{c}\n" for c in codes))
    lab = S.read_sheet(p)
    kept = 1 + 2 * len(keep)                                          # the header is row 1
    assert lab["rows"] == list(range(2, 2 + kept)) and len(lab["values"]) == kept
    assert [(s["row"], s["failure"]) for s in lab["screened"]] == list(zip(range(2 + kept, 2 + len(codes)),
                                                                           codes[kept:]))
    p.write_text(head + f"{cells},ok\n{cells},ok\n{cells},cracked\n")
    with pytest.raises(InputError) as e:
        S.read_sheet(p)
    assert e.value.field == "lab.csv row 4, column 'failure'"


def test_the_bond_wrench_sheets_unit_failure_is_named_as_the_docs_give_it():
    """The reason the docs' worked example prints for the screened row 14."""
    assert S.read_sheet(BOND_SHEET)["screened"][0]["reason"] == "broke through a unit: it measured the unit, not the bond"


def test_a_results_column_in_the_unit_asked(tmp_path):
    """A results column is read in the unit the caller's study takes: a
    fracture energy in N/mm as N/m (x 1000), kPa as Pa (x 1000), N/mm2 as Pa
    (x 1e6); a column of another dimension than the one asked is refused."""
    p = tmp_path / "lab.csv"
    p.write_text("G_f [N/mm]\n0.010\n0.012\n0.011\n")
    assert list(S.read_sheet(p, "N/m")["values"]) == pytest.approx([10.0, 12.0, 11.0], rel=1e-12)
    with pytest.raises(InputError):
        S.read_sheet(p)                                               # N/mm is no stress
    p.write_text("f_tj [kPa]\n300\n410\n330\n")
    assert list(S.read_sheet(p)["values"]) == pytest.approx([3e5, 4.1e5, 3.3e5], rel=1e-12)
    p.write_text("f_tj [N/mm2]\n0.30\n0.41\n0.33\n")
    assert list(S.read_sheet(p, "Pa")["values"]) == pytest.approx([3e5, 4.1e5, 3.3e5], rel=1e-12)


@pytest.mark.parametrize("depth, factor", [(0.050, 1 / 1.55), (0.100, 1 / 1.5), (0.102, 1 / 1.498), (0.4, 1 / 1.2),
                                           (0.6, 1.0), (0.9, 1.0)])
def test_conversion_at_depths_worked_by_hand(depth, factor):
    """EN 1992-1-1, eq. (3.23): 1 / max(1.6 - h/1000, 1), h in mm: 0.645161
    at the unit's 50 mm, 0.666667 at the joint's 100 mm, 1 from 600 mm;
    both flexural tests alike."""
    for measured in ("flexural_bond", "modulus_of_rupture"):
        assert S.conversion(measured, depth)[0] == pytest.approx(factor, rel=1e-12)


def test_a_raw_sheet_with_the_labs_computed_strengths(tmp_path):
    """The worked example's bond-wrench sheet with one more column, the
    strengths a lab computed from the loads by the same formula, worked
    here from the statics by hand ((F1 e1 + F2 e2) / (b d^2 / 6) -
    (F1 + F2 + F3) / (b d)) and written to 2 decimals in N/mm2: read, the
    same values as without it (the loads' strengths, not the rounded
    ones), the method saying the lab's column agrees.  One cell 2 % off is
    refused naming its row and the column; a column of another formula
    (the lever arm taken 50 mm shorter, from the joint's face) is refused
    on its first row."""
    text = open(BOND_SHEET).read()
    lines = text.splitlines()
    head = next(i for i, t in enumerate(lines) if t.startswith("specimen,"))

    def strength(cells, arm=0.0):
        F1, e1, F2, e2, F3, b, d = (float(x) for x in cells[1:8])
        F1, F2, F3, e1, e2, b, d = F1, F2, F3, (e1 - arm) / 1e3, e2 / 1e3, b / 1e3, d / 1e3
        return ((F1 * e1 + F2 * e2) / (b * d ** 2 / 6) - (F1 + F2 + F3) / (b * d)) / 1e6

    def with_column(f, name="f_w [N/mm2]"):
        out = lines[:head] + [lines[head] + f",{name}"]
        out += [t + f",{f(t.split(','), k):.2f}" for k, t in enumerate(lines[head + 1:])]
        p = tmp_path / "with.csv"
        p.write_text("\n".join(out) + "\n")
        return p

    plain = S.read_sheet(BOND_SHEET)
    lab = S.read_sheet(with_column(lambda c, k: strength(c)))
    assert list(lab["values"]) == list(plain["values"]) and lab["screened"] == plain["screened"]
    assert "the lab's column 'f_w [N/mm2]' agrees with it" in lab["method"]
    with pytest.raises(InputError) as e:
        S.read_sheet(with_column(lambda c, k: strength(c) * (1.02 if k == 3 else 1.0)))
    row = head + 1 + 3 + 1                                     # the header's line, then the fourth specimen
    assert e.value.field == f"with.csv row {row}, column 'f_w [N/mm2]'"
    assert "where the loads give" in e.value.reason and "another formula" in e.value.reason
    with pytest.raises(InputError) as e:
        S.read_sheet(with_column(lambda c, k: strength(c, arm=50.0)))
    assert e.value.field == f"with.csv row {head + 2}, column 'f_w [N/mm2]'"


WALL = "specimen,direction,load [kN],support span [mm],load span [mm],width [mm],thickness [mm],failure\n"


def test_a_wallette_sheet_by_statics_with_each_tests_direction(tmp_path):
    """EN 1052-2 wallettes: two loads F/2 at (l1 -+ l2)/2 of a span l1, the
    midspan moment by statics over b t^2 / 6, to 1e-9; each test's
    direction as written (parallel is vertical, perpendicular horizontal);
    the committed synthetic sheet reads too."""
    p = tmp_path / "w.csv"
    p.write_text(WALL + "V1,vertical,3.0,540,180,440,100,bed joint\nV2,parallel,3.5,540,180,440,100,\n"
                        "H1,Horizontal,9.0,742,238,470,100,stepped\nH2,perpendicular,9.5,700,300,400,110,\n")
    lab = S.read_sheet(p)
    expected = [_midspan_moment_stress([(F / 2, (l1 - l2) / 2), (F / 2, (l1 + l2) / 2)], l1, b, t)
                for F, l1, l2, b, t in ((3e3, 0.54, 0.18, 0.44, 0.1), (3.5e3, 0.54, 0.18, 0.44, 0.1),
                                        (9e3, 0.742, 0.238, 0.47, 0.1), (9.5e3, 0.7, 0.3, 0.4, 0.11))]
    assert list(lab["values"]) == pytest.approx(expected, rel=1e-9) and lab["form"] == "wallette"
    assert lab["directions"] == ["vertical", "vertical", "horizontal", "horizontal"]
    assert list(lab["levels"]) == [0.0] * 4
    committed = S.read_sheet("config/lab/waal_wallettes.csv")
    assert len(committed["values"]) == 7 and "SYNTHETIC" in open("config/lab/waal_wallettes.csv").read(200)


def test_a_wallette_sheet_without_its_direction_is_refused(tmp_path):
    """A wallette sheet whose direction is not stated, or stated as no
    direction, is refused naming the column (and the row)."""
    p = tmp_path / "w.csv"
    p.write_text(WALL.replace("direction,", "") + "V1,3.0,540,180,440,100,\nV2,3.5,540,180,440,100,\n"
                                                  "V3,3.1,540,180,440,100,\n")
    with pytest.raises(InputError, match="states each test's direction"):
        S.read_sheet(p)
    p.write_text(WALL + "V1,vertical,3.0,540,180,440,100,\nV2,diagonal,3.5,540,180,440,100,\n"
                        "V3,vertical,3.1,540,180,440,100,\n")
    with pytest.raises(InputError) as e:
        S.read_sheet(p)
    assert e.value.field == "w.csv row 3, column 'direction'" and "no direction" in e.value.reason
