"""A figure's PNG states the height of its smallest text (analysis.plots),
which the report's checks scale to the width the report shows it at."""
import zipfile
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from masonrydem.analysis import plots  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
# the width the report gives a figure at 1280 x 800 beside its widest
# navigation, as the browser test measures it (tests/test_report_browser.py
# checks every figure as shown; this guard runs where there is no browser)
SHOWN_PX = 758


def test_the_smallest_text_is_its_font_size_in_pixels(tmp_path):
    """Text of 7 pt at 150 dpi is 7 x 150 / 72 = 14.58 pixels high, the
    figure's other text (10 pt) larger; an invisible or empty text counts
    for nothing."""
    fig, ax = plt.subplots()
    ax.set_title("a title", fontsize=10)
    ax.text(0.5, 0.5, "small", fontsize=7)
    ax.text(0.5, 0.2, "hidden", fontsize=3, visible=False)
    ax.text(0.5, 0.1, " ", fontsize=2)
    ax.tick_params(labelsize=12)
    path = tmp_path / "f.png"
    plots.save_figure(fig, path, dpi=150)
    assert plots.smallest(path) == pytest.approx(7 * 150 / 72, abs=0.01)


def test_a_picture_written_elsewhere_is_marked(tmp_path):
    """A PNG not written by matplotlib (a 3-D picture) gets the chunk, and
    stays a PNG of the same pixels."""
    fig = plt.figure(figsize=(1, 1))
    path = tmp_path / "p.png"
    fig.savefig(path, dpi=50)
    plt.close(fig)
    assert plots.smallest(path) is None
    before = plt.imread(path)
    plots.mark(path, 18)
    assert plots.smallest(path) == 18.0 and (plt.imread(path) == before).all()


def test_every_figure_of_the_committed_report_states_a_readable_smallest_text(tmp_path):
    """Each figure of results/report.zip states its smallest text, and at
    the report's width (SHOWN_PX, or its own if narrower) it reads at 9
    pixels or more."""
    small = {}
    with zipfile.ZipFile(ROOT / "results/report.zip") as z:
        for name in (n for n in z.namelist() if n.endswith(".png") and "/data/raw/" in n):
            path = z.extract(name, tmp_path)
            px = plots.smallest(path)
            width = plt.imread(path).shape[1]
            if px is None or px * min(1.0, SHOWN_PX / width) < 9:
                small[name] = (px, width)
    assert not small, small
