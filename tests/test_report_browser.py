"""The committed report (results/report.zip) in a real browser: headless
Chromium (Debian's package `chromium`; skipped with the reason where it is
missing).  `make test-browser` runs this file alone and keeps its
screenshots in .test/browser/ to look at.

A probe script is added to a copy of the report's page.  Once the page
has rendered it records, into the DOM that Chromium dumps:
- the landing page's title: where it sits and whether the page's scroll
  box can reach it;
- every link of the landing page that runs code (the report's links to
  its categories and panels): each is run, and an error is recorded;
- every category opened in turn, with the labels of the results it lists;
- a figure taller than the window opened: its top and bottom once its
  view is scrolled to either end.
Each view is also opened on its own page for a screenshot, at 1280x800 and
1920x1080."""
import json
import re
import shutil
import struct
import subprocess
import zipfile
from pathlib import Path

import pandas as pd
import pytest

from test_report_tables import table_shape

pytestmark = pytest.mark.browser

BROWSER = next((b for b in ("chromium", "chromium-browser", "google-chrome") if shutil.which(b)), None)
REPORT = Path("results/report.zip")
SIZES = [(1280, 800), (1920, 1080)]
SHOTS = Path(".test/browser")
# the tables the issue found cut off or downloaded instead of shown
KEY_TABLES = ["statistics", "equations", "paper_comparison", "hard_cases", "reduced", "accuracy_subsample"]

PROBE = """
<script>
const wait = ms => new Promise(r => setTimeout(r, ms));
async function probe() {
  for (let i = 0; i < 60 && !document.querySelector(".prose"); i++) await wait(250);
  const out = {};
  const title = document.querySelector(".prose h1, .prose .title, .prose h2");
  out.title = title ? title.textContent.trim() : null;
  if (title) {
    const r = title.getBoundingClientRect();
    out.title_top = r.top;
    out.title_reachable = r.top >= 0;
  }
  out.link_errors = [];
  const links = [...document.querySelectorAll(".prose a[href^='javascript:']")];
  out.links = links.length;
  for (const a of links) {
    try { (0, eval)(decodeURIComponent(a.getAttribute("href").slice("javascript:".length))); }
    catch (err) { out.link_errors.push(a.textContent + ": " + err); }
  }
  await wait(200);
  out.categories = {};
  for (const cat of Object.keys(categories)) {
    app.showCategory(cat);
    await wait(200);
    const subs = Object.keys(categories[cat]);
    if (subs.length > 1) { app.setView({navbarMode: "subcategory", category: cat, subcategory: subs[0]}); await wait(200); }
    out.categories[cat] = document.querySelector("nav, .h-screen.overflow-auto").innerText;
  }
  out.labels = Object.fromEntries(Object.entries(results).map(([k, r]) => [k, r.labels]));
  out.mime = Object.fromEntries(Object.entries(results).map(([k, r]) => [k, r.mime_type]));
  // the tallest figure, opened as the report opens a figure
  const tall = TALL;
  app.setView({content: "img", contentPath: results[tall].data_uri, resultPath: tall});
  for (let i = 0; i < 40 && !(document.querySelector(".h-screen.overflow-auto img") || {}).complete; i++) await wait(100);
  await wait(300);
  const img = document.querySelector(".h-screen.overflow-auto img");
  const box = img.closest(".overflow-auto");
  box.scrollTop = 0; box.scrollLeft = 0;
  await wait(50);
  const top = img.getBoundingClientRect();
  box.scrollTop = box.scrollHeight;
  await wait(50);
  const bottom = img.getBoundingClientRect();
  out.tall = {path: tall, top: top.top, left: top.left, bottom: bottom.bottom, window: window.innerHeight,
              height: top.height, width: top.width, window_width: window.innerWidth};
  const pre = document.createElement("pre");
  pre.id = "probe";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
}
window.addEventListener("load", probe);
</script>
"""

VIEW = """
<script>
window.addEventListener("load", () => setTimeout(() => { VIEW }, 1500));
</script>
"""


FIGURES = """
<script>
const wait = ms => new Promise(r => setTimeout(r, ms));
async function probe() {
  for (let i = 0; i < 60 && !document.querySelector(".prose"); i++) await wait(250);
  const out = {};
  for (const [cat, subs] of Object.entries(categories)) {
    for (const [sub, keys] of Object.entries(subs)) {
      for (const key of keys) {
        if (results[key].mime_type !== "image/png") continue;
        // as a reader opens it: the category's list in the navigation, the figure beside it
        app.setView({navbarMode: "subcategory", category: cat, subcategory: sub, content: "img",
                     contentPath: results[key].data_uri, resultPath: key});
        let img = null;
        for (let i = 0; i < 50; i++) {
          await wait(100);
          img = [...document.querySelectorAll("img")].find(x => x.getAttribute("src") === results[key].data_uri);
          if (img && img.complete && img.naturalWidth) break;
        }
        await wait(100);
        out[key] = img ? {shown: img.getBoundingClientRect().width, natural: img.naturalWidth,
                          nav: (document.querySelector("nav") || {getBoundingClientRect: () => ({width: 0})})
                               .getBoundingClientRect().width} : null;
      }
    }
  }
  const pre = document.createElement("pre");
  pre.id = "probe";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
}
window.addEventListener("load", probe);
</script>
"""
# the smallest text a figure may show, in the screen's pixels at 1280 x 800
SMALLEST_PX = 9


def _chromium(page, size, *args):
    cmd = [BROWSER, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
           f"--window-size={size[0]},{size[1]}", "--virtual-time-budget=30000", *args, page.as_uri()]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=180)


def _png_size(path):
    with open(path, "rb") as f:
        return struct.unpack(">II", f.read(24)[16:24])


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    if BROWSER is None:
        pytest.skip("no Chromium (Debian: apt-get install chromium)")
    root = tmp_path_factory.mktemp("report")
    with zipfile.ZipFile(REPORT) as z:
        z.extractall(root)
    return root / "report" / "report.html"


def _tallest(page):
    """The report's figure of the most pixels in height (read from its PNG)."""
    pngs = list(page.parent.glob("data/raw/*/*.png"))
    return max(pngs, key=lambda p: _png_size(p)[1])


def _with(page, name, script):
    """A copy of the report's page with ``script`` added at its end."""
    head, tag, tail = page.read_text().rpartition("</body>")   # the page's own (JS strings hold others)
    out = page.with_name(name)
    out.write_text(head + script + tag + tail)
    return out


def _probe(report, size):
    tall = _tallest(report)
    key = next(k for k in json.loads(re.search(r"var results = (\{.*?\});\n", report.read_text(), re.S)[1])
               if k.endswith("/" + tall.name) or k == tall.name)
    probed = _with(report, "probed.html", PROBE.replace("TALL", json.dumps(key)))
    dom = _chromium(probed, size, "--dump-dom").stdout
    found = re.search(r'<pre id="probe">(.*?)</pre>', dom, re.S)
    assert found, "the probe did not run: the report page did not render"
    return json.loads(found[1].replace("&quot;", '"').replace("&amp;", "&").replace("&lt;", "<")
                      .replace("&gt;", ">")), tall


@pytest.mark.parametrize("size", SIZES, ids=[f"{w}x{h}" for w, h in SIZES])
def test_every_view_is_within_reach(report, size):
    """The landing page's title on screen, its links run, every category
    lists its results by their labels, and a figure taller than the window
    can be scrolled to its top and its bottom."""
    probe, tall = _probe(report, size)
    assert probe["title"] and probe["title"].startswith("masonrydem"), probe["title"]
    assert probe["title_reachable"], probe["title_top"]
    assert probe["links"] >= 10 and not probe["link_errors"], probe["link_errors"]
    # every result labelled, and each category lists its results by label
    unlabelled = [k for k, v in probe["labels"].items() if not (v and all(v.values()))]
    assert not unlabelled, unlabelled
    assert len(probe["categories"]) >= 8, list(probe["categories"])
    for cat, text in probe["categories"].items():
        assert text.strip(), f"category {cat} shows nothing"
    # no result is a CSV, which the report would only offer for download
    assert not [k for k, m in probe["mime"].items() if m == "text/csv"], probe["mime"]
    # the tall figure: taller than the window (by its PNG), yet its top and bottom within reach
    t = probe["tall"]
    assert _png_size(tall)[1] > size[1], (tall, _png_size(tall))
    assert t["top"] >= 0 and t["left"] >= 0 and t["bottom"] <= t["window"] + 1, t
    assert t["width"] <= t["window_width"], t


def _views(report, tall_key):
    """Views to screenshot: the landing page, each category, the run times,
    the tall figure scrolled to its top."""
    cats = json.loads(re.search(r"var categories = (\{.*?\});\n", report.read_text(), re.S)[1])
    views = {"landing": "", "landing_end": "document.querySelectorAll('.overflow-auto').forEach(b => b.scrollTop = b.scrollHeight);"}
    views |= {f"category_{re.sub('[^a-z0-9]+', '_', c.lower())}": f"app.showCategory({json.dumps(c)});" for c in cats}
    views["runtimes"] = "app.setView({content: 'stats'});"
    views["tall_figure"] = (f"app.setView({{content: 'img', contentPath: results[{json.dumps(tall_key)}].data_uri, "
                            f"resultPath: {json.dumps(tall_key)}}});")
    return views


@pytest.mark.parametrize("size", SIZES, ids=[f"{w}x{h}" for w, h in SIZES])
def test_screenshots_of_every_view(report, size):
    """A screenshot of each view (.test/browser/, to look at)."""
    SHOTS.mkdir(parents=True, exist_ok=True)
    tall = _tallest(report)
    key = next(k for k in json.loads(re.search(r"var results = (\{.*?\});\n", report.read_text(), re.S)[1])
               if k.endswith("/" + tall.name) or k == tall.name)
    for name, script in _views(report, key).items():
        page = _with(report, f"view_{name}.html", VIEW.replace("VIEW", script))
        shot = SHOTS / f"{name}_{size[0]}x{size[1]}.png"
        r = _chromium(page, size, f"--screenshot={shot.resolve()}")
        assert r.returncode == 0 and shot.stat().st_size > 5000, (name, r.stderr[-2000:])


def _table_page(report, name):
    results = json.loads(re.search(r"var results = (\{.*?\});\n", report.read_text(), re.S)[1])
    key = next(k for k in results if k.endswith(f"tables/{name}.html"))
    return report.parent / results[key]["data_uri"]


@pytest.mark.parametrize("name", KEY_TABLES)
def test_the_tables_show_every_row_of_their_csv_within_the_window(report, name):
    """A table page holds every row of its CSV (as a row, or as a column
    where the page transposed a wide table), and at 1280 px its widest row
    fits the window, so no column is out of sight (the hard cases' table,
    of 17 columns and 22 rows, scrolls beside its key columns)."""
    csv = {"hard_cases": "stability/hard_cases.csv", "reduced": "reduced/summary.csv",
           "accuracy_subsample": "accuracy/subsample.csv"}.get(name, f"study/{name}.csv")
    table = pd.read_csv(Path("results") / csv)
    page = _table_page(report, name)
    rows, cells = table_shape(page.read_text())
    transposed = re.search(r"<table[^>]*transposed", page.read_text()) is not None
    assert (cells - 1 if transposed else rows) == len(table), ((rows, cells), table.shape)
    probed = _with(page, f"probed_{name}.html", """<script>window.addEventListener("load", () => {
      const pre = document.createElement("pre"); pre.id = "probe";
      pre.textContent = JSON.stringify(Math.max(...[...document.querySelectorAll("tr")].map(
        r => r.getBoundingClientRect().right)));
      document.body.appendChild(pre); });</script>""")
    dom = _chromium(probed, SIZES[0], "--dump-dom").stdout
    right = float(re.search(r'<pre id="probe">(.*?)</pre>', dom, re.S)[1])
    # the window's width (the report's navigation beside it can be hidden)
    assert right <= SIZES[0][0] or name == "hard_cases", right


def test_every_figure_s_smallest_text_reads_at_9_pixels_as_shown(report):
    """Each figure of the report opened as a reader opens it (its
    category's list in the navigation beside it) at 1280 x 800: the height
    of its smallest text, as its PNG states it (analysis.plots; the 3-D
    pictures' VTK font size), times the scale the report shows it at, is
    9 pixels or more.  A figure that states no size fails too."""
    from masonrydem.analysis.plots import smallest
    probed = _with(report, "probed_figures.html", FIGURES)
    dom = _chromium(probed, SIZES[0], "--dump-dom").stdout
    found = re.search(r'<pre id="probe">(.*?)</pre>', dom, re.S)
    assert found, "the probe did not run"
    shown = json.loads(found[1].replace("&quot;", '"').replace("&amp;", "&"))
    results = json.loads(re.search(r"var results = (\{.*?\});\n", report.read_text(), re.S)[1])
    pngs = [k for k, r in results.items() if r["mime_type"] == "image/png"]
    assert sorted(shown) == sorted(pngs)
    small = {}
    for key in pngs:
        s = shown[key]
        assert s and s["natural"], (key, s)
        px = smallest(report.parent / results[key]["data_uri"])
        on_screen = (px or 0) * s["shown"] / s["natural"]
        if on_screen < SMALLEST_PX:
            small[key] = (px, round(s["shown"]), s["natural"], round(on_screen, 1))
    assert not small, "figures whose smallest text reads below 9 px (stated px, shown width, PNG width, " \
                      "px on screen): " + json.dumps(small, indent=1)
