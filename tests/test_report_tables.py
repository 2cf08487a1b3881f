"""The report's table pages (report/tables.py), the landing page's
comparison with the paper (report/landing.py) and the check of the
records' run times before a report is built (pipeline/snakemake_state.py)."""
import datetime
import sys
import pandas as pd

from masonrydem.pipeline.snakemake_state import building_report, record_times_error
from masonrydem.report import landing, tables


def test_headers_carry_the_unit_their_column_name_ends_in():
    assert tables.header("P_max_mean_kN").endswith("(kN)")
    assert tables.header("sigma_v_mpa").endswith("(MPa)")
    assert tables.header("initial_stiffness_kN_per_mm").endswith("(kN/mm)")
    assert tables.header("difference_pct").endswith("(%)")
    assert "_" not in tables.header("mode_as_expected")     # words, not a code name


def test_a_value_and_its_interval_share_one_cell_and_keys_come_first():
    t = pd.DataFrame({"ours": [1.23456, 2.0], "ours_lo": [1.0, 1.5], "ours_hi": [1.5, 2.5], "mode": ["a", "b"]})
    r = tables.readable(t)
    assert list(r.columns)[0] == "mode" and r.shape == (2, 2)
    cell = r.iloc[0, 1]
    assert cell == "1.235 (1.000 to 1.500)"     # rounded to one precision, then lo to hi


def test_a_wide_short_table_is_transposed_and_keeps_every_row():
    wide = pd.DataFrame({"mode": ["joint", "brick", "all"], **{f"c{i}": [i, i + 1, i + 2] for i in range(20)}})
    assert table_shape(tables.html_table(wide, "wide")) == (20, 4)    # a row per column, a column per row
    long = pd.DataFrame({"mode": ["joint"] * 30, "x": range(30)})
    assert table_shape(tables.html_table(long, "long")) == (30, 2)


def test_the_model_form_band_is_the_envelope_of_the_neighbouring_levels():
    summary = pd.DataFrame({"case": ["joint"] * 6, "sigma_v_mpa": [0, 0, 0, 0.5, 0.5, 0.5],
                            "assumption": ["baseline", "a", "b", "baseline", "a", "b"],
                            "change_pct": [0, -4, 10, 0, -20, 3]})
    band = landing.modelform_band(summary)
    assert landing.band_at(band, "joint", 0.0) == (-4, 10)
    assert landing.band_at(band, "joint", 0.25) == (-20, 10)       # between the two: both
    assert landing.band_at(band, "all", 0.5) == (-20, 3)           # no such case: every case


def test_the_landing_page_counts_the_papers_figures_inside_our_interval_and_band():
    card = pd.DataFrame({"item": ["F_max mean (kN)"] * 2 + ["F_max COV"], "mode": ["all", "all", "all"],
                         "sigma_v_mpa": [0.0, 0.5, 0.0], "paper": [10.0, 10.0, 0.3], "ours": [10.5, 11.5, 0.3],
                         "ours_lo": [9.8, 11.0, 0.2], "ours_hi": [11.0, 12.0, 0.4], "difference_pct": [5, 15, 0],
                         "paper_inside": [True, False, True]})
    band = {"joint": {0.0: [-10.0, 5.0], 0.5: [-5.0, 5.0]}}
    text = landing.paper_findings(card, band)
    # 10.0 inside 10.5 x (0.9, 1.05); 10.0 below 11.5 x 0.95 = 10.925
    assert "**1 of 2**" in text.split("interval")[1] and "band" in text
    assert text.count("**no**") == 2        # the second level: outside both


def _t(*date):
    return datetime.datetime(*date).timestamp()


def test_a_record_with_an_impossible_time_is_named():
    assert record_times_error({"starttime": _t(2026, 11, 28, 4), "endtime": _t(2026, 11, 28, 5)}) is None
    assert "before 2026" in record_times_error({"starttime": _t(2026, 11, 28), "endtime": 0})
    assert "before it starts" in record_times_error({"starttime": _t(2026, 11, 28, 5), "endtime": _t(2026, 11, 28)})
    assert "missing" in record_times_error({"starttime": None, "endtime": _t(2026, 11, 28)})
    assert "before 2026" in record_times_error({"starttime": _t(2025, 12, 31), "endtime": _t(2026, 1, 2)})


def test_a_report_is_recognised_from_snakemakes_options():
    assert building_report(["snakemake", "--report", "r.zip", "all"])
    assert building_report(["snakemake", "--report=r.zip"])
    assert not building_report(["snakemake", "--cores", "2", "all"])
    assert building_report() == ("--report" in sys.argv)


def table_shape(html):
    """(rows, cells of its first row) of the first table body in ``html``:
    a reading of the page independent of the code that wrote it."""
    from html.parser import HTMLParser

    class Cells(HTMLParser):
        rows, body, done = [], False, False

        def handle_starttag(self, tag, attrs):
            if tag == "tbody" and not self.done:
                self.body = True
            elif self.body and tag == "tr":
                self.rows.append(0)
            elif self.body and tag in ("td", "th"):
                self.rows[-1] += 1

        def handle_endtag(self, tag):
            if tag == "tbody" and self.body:
                self.body, self.done = False, True
    p = Cells()
    p.rows = []
    p.feed(html)
    return len(p.rows), p.rows[0] if p.rows else 0


def _committed_report():
    """The committed report's results and its categories, read from the
    JSON its page carries (results/report.zip)."""
    import json
    import re
    import zipfile
    from pathlib import Path
    with zipfile.ZipFile(Path(__file__).resolve().parents[1] / "results/report.zip") as z:
        page = z.read("report/report.html").decode()
    return [json.loads(re.search(rf"var {name} = (\{{.*?\}});\n", page, re.S)[1]) for name in ("results", "categories")]


def test_every_result_of_the_committed_report_is_listed_once_by_a_label_of_its_own():
    """Snakemake's report lists a category's results by their labels, one
    per label: two results of one label in a category leave one of them
    unreachable (and search finds it by the same lookup).  So each
    (category, subcategory) holds distinct labels, and the results listed
    are the results the report carries."""
    results, categories = _committed_report()
    listed = [(cat, sub, key) for cat, subs in categories.items() for sub, keys in subs.items() for key in keys]
    assert sorted(k for *_, k in listed) == sorted(results)
    seen = {}
    for cat, sub, key in listed:
        label = tuple(sorted(results[key]["labels"].items()))
        assert (cat, sub, label) not in seen, (cat, sub, label, key, seen.get((cat, sub, label)))
        seen[(cat, sub, label)] = key


def test_a_column_shows_its_numbers_to_one_precision_and_an_error_in_percent():
    """Every number of a column to the same decimals (4 significant digits
    of its largest value, at least 2 of its smallest), a relative error (a fraction
    in the CSV) in % with its interval, and a page of correlations without
    its inputs' units (its level with its unit)."""
    t = pd.DataFrame(dict(case=["a", "b"], difference_pct=[3.229, -25.0], max_abs_error=[0.01649, 0.0042],
                          mean_diff=[-0.001459, 0.0004], mean_diff_lo=[-0.002, -0.001], mean_diff_hi=[0.0, 0.002]))
    r = tables.readable(t)
    assert list(r["difference (%)"]) == ["3.23", "-25.00"]
    assert list(r["max abs error (%)"]) == ["1.649", "0.420"]
    assert list(r["mean diff (%), 95 % interval"]) == ["-0.1459 (-0.2000 to 0.0000)", "0.0400 (-0.1000 to 0.2000)"]
    corr = pd.DataFrame(dict(variant=["v"], sigma_v_mpa=[0.15], f_tj_mpa=[0.92], phi_j_deg=[-0.05]))
    assert list(tables.readable(corr, units=False).columns) == ["variant", "σ<sub>v</sub> (MPa)", "f<sub>tj</sub>",
                                                                "φ<sub>j</sub>"]      # the level keeps its unit
    assert "f<sub>tj</sub> (MPa)" in tables.readable(corr).columns
