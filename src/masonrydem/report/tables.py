"""The report's tables as HTML pages (the report shows an HTML result in
place; a CSV it only offers for download).  A page is the CSV made
readable, never changed in substance:
- the headers in engineering names with their units, read from the
  column names' suffixes (``P_max_mean_kN`` -> P_max mean (kN));
- a value with its 95 % interval (columns ``x``, ``x_lo``, ``x_hi``) in one
  cell, "x (lo to hi)";
- numbers to 4 significant digits, every number of a column to the same
  decimals, yes/no for true/false;
- a relative error or difference (FRACTIONS) in %, as the captions give it;
- a page of correlations (``units=False``) with its inputs' names alone,
  no units (a correlation has none), its key columns (the level) with theirs;
- the key columns (what a row is: item, variant, case, mode, level) first;
- a table wider than it is long, of more than ``WIDE`` columns,
  transposed: one column per row of the CSV.
The CSV stays the data (results/, beside the page)."""
from html import escape

import numpy as np
import pandas as pd

# what a row is, in this order, before every other column
KEYS = ("item", "format", "variant", "case", "run", "test", "model", "setting", "assumption", "option", "variable",
        "input", "quantity", "against", "mode", "sigma_v_mpa")
# a table of more columns than this, and fewer rows, reads better transposed
WIDE = 9
# units by the column name's suffix (longest first)
UNITS = (("_kN_per_mm", "kN/mm"), ("_kN", "kN"), ("_mpa", "MPa"), ("_MPa", "MPa"), ("_mm", "mm"), ("_pct", "%"),
         ("_deg", "°"), ("_us", "µs"), ("_s", "s"), ("_m", "m"))
# abbreviations as engineering texts write them; Greek letters by name
WORDS = {"cov": "COV", "mape": "MAPE", "cv": "CV", "sd": "SD", "r2": "R²", "lg": "Lourenço-Gaetani",
         "as3700": "AS 3700", "S1": "S<sub>1</sub>", "ST": "S<sub>T</sub>"}
# columns that hold a relative error or difference (a fraction), shown in %
FRACTIONS = ("error", "finest_error", "last_two_diff", "max_abs_error", "mean_diff", "cov_diff", "peak_error",
             "residual_error")
GREEK = {"alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ε", "eta": "η", "theta": "θ",
         "kappa": "κ", "lambda": "λ", "mu": "μ", "nu": "ν", "rho": "ρ", "sigma": "σ", "tau": "τ", "phi": "φ",
         "psi": "ψ", "omega": "ω"}


def _unit(word):
    return next((u for suffix, u in UNITS if suffix[1:] == word), None)


def header(name, units=True):
    """A column's header: a symbol as engineering texts write it (a letter,
    a Greek one by its name, then a short subscript: f_tj as f<sub>tj</sub>),
    other parts as words, the unit its name ends in last (``units``: False
    for a column of a dimensionless quantity named after an input)."""
    unit = next((u for suffix, u in UNITS if name.endswith(suffix) and len(name) > len(suffix)), None)
    stem = name[:-len(next(s for s, u in UNITS if u == unit and name.endswith(s)))] if unit else name
    stem, square = (stem[:-2], "²") if stem.endswith("^2") else (stem, "")
    parts, words = stem.split("_"), []
    while parts:
        head = parts.pop(0)
        letter = GREEK.get(head, head if len(head) == 1 else None)
        if letter and parts and len(parts[0]) <= 3 and not _unit(parts[0]):
            words.append(f"{letter}<sub>{escape(parts.pop(0))}</sub>")
        elif letter:
            words.append(letter)
        else:
            words.append(f"({_unit(head)})" if _unit(head) else WORDS.get(head, escape(head)))
    text = " ".join(words) + square
    return f"{text} ({unit})" if unit and units else text


def decimals(values):
    """The decimals a column of numbers is shown to: 4 significant digits
    of its largest value, and at least 2 of its smallest of 0.001 or more
    (at most 6 decimals); a smaller value keeps 4 significant digits of
    its own."""
    x = np.abs(np.asarray(values, float))
    x = x[np.isfinite(x) & (x >= 1e-3)]
    if not len(x):
        return None
    e = np.floor(np.log10(x))
    return int(min(6, max(0, 3 - e.max(), 1 - e.min())))


def _cell(x, places=None):
    if isinstance(x, (bool, np.bool_)):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(x)
    if isinstance(x, (float, np.floating)):
        if np.isnan(x):
            return ""
        return f"{x:.{places}f}" if places is not None and (x == 0 or abs(x) >= 1e-3) else f"{x:.4g}"
    if pd.isna(x):
        return ""
    return escape(str(x)) if len(str(x)) <= 40 else f'<span class="long">{escape(str(x))}</span>'    # a sentence wraps


def _column(values, item=None):
    """A column's cells (with its interval's columns, ``values``) as text:
    its floats to the decimals of the column, or of each quantity where
    the rows are of several (``item``)."""
    floats = [c for c in values if values[c].dtype.kind == "f"]
    out = values.astype(object).map(_cell)
    if not floats or values.columns[0] in KEYS:
        return out.where(~values.isna() | ~values.columns.isin(floats), "") if floats else out
    for _, rows in (values.groupby(item, sort=False) if item is not None else [(None, values)]):
        places = decimals(rows[floats].to_numpy().ravel())
        out.loc[rows.index, floats] = rows[floats].map(lambda x: _cell(x, places))
    return out


def readable(table, units=True):
    """The page's table: key columns first, intervals joined, values as
    text (a frame of strings with HTML headers); a column without a single
    value (an output too few runs cannot give: the caption says why) is
    left out."""
    cols = [c for c in KEYS if c in table] + [c for c in table if c not in KEYS]
    cols = [c for c in cols if table[c].notna().any()]
    out = {}
    for c in cols:
        if c.endswith(("_lo", "_hi")) and c[:-3] in table:
            continue
        group = [x for x in (c, f"{c}_lo", f"{c}_hi") if x in table]
        cells = _column(table[group] * (100 if c in FRACTIONS else 1) if c in FRACTIONS else table[group],
                        table.get("item") if c not in KEYS else None)
        text = cells[c]
        name = header(c, units or c in KEYS) + (" (%)" if c in FRACTIONS else "")
        if len(group) == 3:
            lo, hi = (cells[x] for x in group[1:])
            text = text + np.where(lo.ne("") & hi.ne(""), " (" + lo + " to " + hi + ")", "")
            out[f"{name}, 95 % interval"] = text
        else:
            out[name] = text
    return pd.DataFrame(out)


def html_page(tables, title, units=True):
    """An HTML page of one or more (heading, table) pairs under ``title``;
    a wide table transposed.  The header row (or column) stays in view
    as the page scrolls."""
    parts = []
    for heading, table in tables:
        t = readable(table, units)
        if t.shape[1] > WIDE and len(t) < t.shape[1]:
            keys = [header(c, True) for c in KEYS if c in table and header(c, True) in t][:2]
            names = t[keys].agg(", ".join, axis=1) if keys else pd.Series(range(1, len(t) + 1)).astype(str)
            t = t.drop(columns=keys).T
            t.columns = names
            body = t.to_html(escape=False, border=0, classes="transposed")
        else:
            body = t.to_html(escape=False, border=0, index=False)
        parts.append((f"<h4>{escape(heading)}</h4>\n" if heading else "") + body)
    style = ("body{font:14px sans-serif;margin:8px} table{border-collapse:collapse;margin-bottom:1.5em} "
             "th,td{padding:3px 8px;text-align:right;border-bottom:1px solid #ddd;vertical-align:top} "
             "td{white-space:nowrap} .long{white-space:normal;display:inline-block;min-width:16em;text-align:left} thead th{position:sticky;top:0;background:#f4f4f4} "
             "table.transposed tbody th{position:sticky;left:0;background:#f4f4f4;text-align:left} "
             "tr:hover td{background:#fafae0}")
    return (f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>{escape(title)}</title>'
            f"<style>{style}</style></head>\n<body><h3>{escape(title)}</h3>\n" + "\n".join(parts)
            + "\n</body></html>\n")


def html_table(table, title, units=True):
    """One table as a page of the report (``units``: False for a table of
    dimensionless values in columns named after the inputs)."""
    return html_page([(None, table)], title, units)
