"""The committed report (results/report.zip) in a real browser: headless
Chromium (Debian's package `chromium`; skipped with the reason where it is
missing).  `make test-browser` runs this file alone and keeps its
screenshots in .test/browser/ to look at.

A probe script is added to a copy of the report's page.  Once the page
has rendered it records, into the DOM that Chromium dumps:
- the landing page's title: where it sits and whether the page's scroll
  box can reach it, at 1280x800 and at 1920x1080;
- every link of the landing page that runs code (the report's links to
  its categories and panels): each is run, and an error is recorded;
- the results the report shows as HTML (the key tables)."""
import json
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

pytestmark = pytest.mark.browser

BROWSER = next((b for b in ("chromium", "chromium-browser", "google-chrome") if shutil.which(b)), None)
REPORT = Path("results/report.zip")
SIZES = [(1280, 800), (1920, 1080)]
KEY_TABLES = ["statistics", "equations", "paper_comparison"]

PROBE = """
<script>
function probe(tries) {
  if (!document.querySelector(".prose") && tries > 0) return setTimeout(() => probe(tries - 1), 500);
  const out = {};
  const title = document.querySelector(".prose h1, .prose .title, .prose h2");
  out.title = title ? title.textContent.trim() : null;
  if (title) {
    const r = title.getBoundingClientRect();
    let box = title.parentElement;
    while (box && getComputedStyle(box).overflowY !== "auto") box = box.parentElement;
    // the title is within reach: on screen, or above it by no more than the box can scroll up
    out.title_top = r.top;
    out.title_reachable = r.top >= 0 || (box !== null && box.scrollTop >= -r.top);
  }
  out.link_errors = [];
  const links = [...document.querySelectorAll(".prose a[href^='javascript:']")];
  out.links = links.length;
  for (const a of links) {
    try { (0, eval)(decodeURIComponent(a.getAttribute("href").slice("javascript:".length))); }
    catch (err) { out.link_errors.push(a.textContent + ": " + err); }
  }
  out.html_results = Object.keys(results).filter(k => results[k].mime_type === "text/html");
  const pre = document.createElement("pre");
  pre.id = "probe";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
}
window.addEventListener("load", () => probe(40));
</script>
"""


def _chromium(page, size, *args):
    cmd = [BROWSER, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
           f"--window-size={size[0]},{size[1]}", "--virtual-time-budget=30000", *args, page.as_uri()]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    if BROWSER is None:
        pytest.skip("no Chromium (Debian: apt-get install chromium)")
    root = tmp_path_factory.mktemp("report")
    with zipfile.ZipFile(REPORT) as z:
        z.extractall(root)
    page = root / "report" / "report.html"
    probed = page.with_name("probed.html")
    head, tag, tail = page.read_text().rpartition("</body>")   # the page's own (JS strings hold others)
    probed.write_text(head + PROBE + tag + tail)
    return probed


@pytest.mark.parametrize("size", SIZES, ids=[f"{w}x{h}" for w, h in SIZES])
def test_the_landing_page_reads_and_its_links_work(report, size, request):
    shots = Path(".test/browser")
    shots.mkdir(parents=True, exist_ok=True)
    shot = shots / f"landing_{size[0]}x{size[1]}.png"
    r = _chromium(report.with_name("report.html"), size, f"--screenshot={shot.resolve()}")
    assert r.returncode == 0 and shot.stat().st_size > 10000, r.stderr[-2000:]
    dom = _chromium(report, size, "--dump-dom").stdout
    found = re.search(r'<pre id="probe">(.*?)</pre>', dom, re.S)
    assert found, "the probe did not run: the report page did not render"
    probe = json.loads(found[1].replace("&quot;", '"').replace("&amp;", "&").replace("&lt;", "<")
                       .replace("&gt;", ">"))
    assert probe["title"] and probe["title"].startswith("masonrydem"), probe
    assert probe["title_reachable"], probe
    assert probe["links"] >= 10 and not probe["link_errors"], probe
    assert all(any(f"tables/{t}.html" in k for k in probe["html_results"]) for t in KEY_TABLES), probe
