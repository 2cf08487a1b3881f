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
    assert cell.index("1.235") < cell.index("1 to") < cell.index("1.5")     # rounded, then lo to hi


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
