"""A figure saved as PNG with the height of its smallest text, in the PNG's
pixels, in a text chunk of its own (``SMALLEST``).  A report shows a
figure scaled to the width it has; that height times the scale is how
large the smallest text reads there, which the report's browser check
measures (tests/test_report_browser.py).  The 3-D pictures, drawn by
VTK, state theirs through ``mark``."""
import struct
import zlib

# the PNG text chunk's keyword
SMALLEST = "smallest text px"


def smallest_text_px(fig, dpi):
    """The smallest visible text of a matplotlib figure, in pixels at
    ``dpi``: its font size in points x dpi / 72."""
    from matplotlib.text import Text
    sizes = [t.get_fontsize() for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]
    return min(sizes) * dpi / 72 if sizes else float("nan")


def save_figure(fig, path, dpi=100, **kwargs):
    """Save ``fig`` as a PNG at ``dpi`` with its smallest text's height,
    and close it.  At 100 dpi a figure is wider than the report shows it,
    and its text at 10 pt reads at 9 px there."""
    import matplotlib.pyplot as plt
    fig.savefig(path, dpi=dpi, metadata={SMALLEST: f"{smallest_text_px(fig, dpi):.2f}"}, **kwargs)
    plt.close(fig)


def mark(path, px):
    """Add the smallest text's height ``px`` to a PNG written elsewhere (a
    3-D picture's screenshot): a tEXt chunk after the header."""
    with open(path, "rb") as f:
        data = f.read()
    body = SMALLEST.encode("latin-1") + b"\0" + f"{px:.2f}".encode("latin-1")
    chunk = struct.pack(">I", len(body)) + b"tEXt" + body + struct.pack(">I", zlib.crc32(b"tEXt" + body))
    end = 8 + 8 + 13 + 4                       # signature, then the IHDR chunk (length, type, 13 bytes, CRC)
    with open(path, "wb") as f:
        f.write(data[:end] + chunk + data[end:])


def smallest(path):
    """The smallest text's height a PNG states (``SMALLEST``), or None."""
    with open(path, "rb") as f:
        data = f.read()
    pos = 8
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        if kind == b"tEXt":
            key, _, value = data[pos + 8:pos + 8 + n].partition(b"\0")
            if key.decode("latin-1") == SMALLEST:
                return float(value)
        pos += 12 + n
    return None
