"""What accuracy costs in time: the convergence reference, the Pareto front
of error against run time, the knee, and power-law cost fits.

A sweep table has one row per run with at least: case, setting, P_max_kN,
failure_mode, ok, wall_time_s, cells (cells per unit, e.g. '7x3x2').
"""
import numpy as np
import pandas as pd
from scipy.optimize import brentq



def richardson(n, P):
    """Generalised Richardson extrapolation from three levels of refinement
    ``n`` (cells per edge, any ratios) with results ``P``, assuming
    P(n) = P_inf + C n^-p.  Returns (P_inf, p), or (nan, nan) when the three
    results are not monotone (no asymptotic range: no estimate)."""
    n = np.asarray(n, float)
    P = np.asarray(P, float)
    order = np.argsort(n)
    n, P = n[order], P[order]
    d1, d2 = P[1] - P[0], P[2] - P[1]
    if d1 == 0 or d2 == 0 or np.sign(d1) != np.sign(d2):
        return np.nan, np.nan
    h = 1.0 / n
    ratio = d1 / d2

    def f(p):
        return (h[1] ** p - h[0] ** p) / (h[2] ** p - h[1] ** p) - ratio

    lo, hi = 0.05, 8.0
    if f(lo) * f(hi) > 0:
        return np.nan, np.nan
    p = brentq(f, lo, hi, xtol=1e-12)
    C = d2 / (h[2] ** p - h[1] ** p)
    return float(P[2] - C * h[2] ** p), float(p)


def reference(path, tolerance=0.01):
    """Converged reference of one case from its refinement path (a table of
    cells_n and P_max_kN, coarse to fine).  The path has converged when its
    two finest levels lie within ``tolerance`` of each other; the reference
    is then the Richardson limit of the three finest levels when they show
    an order (monotone, with shrinking steps), else the finest level.  A path
    whose two finest levels differ by more is flagged NOT CONVERGED (its
    finest level stands, and judges no setting)."""
    path = path.sort_values("cells_n")
    n, P = path["cells_n"].to_numpy(float), path["P_max_kN"].to_numpy(float)
    last_two = abs(P[-1] - P[-2]) / abs(P[-1]) if len(P) >= 2 else np.nan
    P_inf, p = richardson(n[-3:], P[-3:]) if len(P) >= 3 else (np.nan, np.nan)
    if not last_two <= tolerance:
        value, method = P[-1], f"NOT CONVERGED: the two finest levels differ by {100 * last_two:.2f} %"
    elif np.isfinite(P_inf):
        value, method = P_inf, (f"Richardson limit of the three finest levels (observed order {p:.2f}; "
                                f"two finest within {100 * last_two:.2f} %)")
    else:
        value, method = P[-1], (f"finest level (two finest within {100 * last_two:.2f} %; the three finest "
                                "not monotone, or their steps not shrinking: no observed order)")
    return dict(reference_kN=float(value), method=method, order=p, finest_kN=float(P[-1]),
                finest_n=int(n[-1]), last_two_diff=float(last_two), finest_error=float(P[-1] / value - 1.0),
                orders=observed_orders(n, P))


def observed_orders(n, P):
    """The observed order of every three consecutive levels, coarse to fine
    ('-' where they show none: not monotone, or steps not shrinking), e.g.
    '0.9 1.2 1.6': a path in its asymptotic range shows a steady order, one
    that is not yet shows it drifting, and then its Richardson limit is no
    firmer than that drift."""
    orders = [richardson(n[i:i + 3], P[i:i + 3])[1] for i in range(len(P) - 2)]
    return " ".join("-" if not np.isfinite(p) else f"{p:.2f}" for p in orders)


def pareto_front(cost, error):
    """Indices of the runs not dominated in (cost, |error|), by cost."""
    cost, error = np.asarray(cost, float), np.abs(np.asarray(error, float))
    idx = np.argsort(cost, kind="stable")
    front, best = [], np.inf
    for i in idx:
        if error[i] < best:
            front.append(int(i))
            best = error[i]
    return front


def knee(table, tolerance):
    """The cheapest setting whose P_max is within ``tolerance`` of every
    case's reference with the reference's failure mode.  ``table``: one row
    per (setting, case) with error, mode_ok and wall_time_s.  Returns the
    per-setting table (max |error| over cases, all modes right, total time)
    sorted by cost, with a 'knee' column."""
    g = table.groupby("setting").agg(max_abs_error=("error", lambda e: float(np.max(np.abs(e)))),
                                     modes_ok=("mode_ok", "all"), ok=("ok", "all"),
                                     total_time_s=("wall_time_s", "sum"), cases=("case", "count"))
    g = g.reset_index().sort_values("total_time_s", kind="stable").reset_index(drop=True)
    good = (g["max_abs_error"] <= tolerance) & g["modes_ok"] & g["ok"] & (g["cases"] == g["cases"].max())
    g["knee"] = False
    if good.any():
        g.loc[good.idxmax(), "knee"] = True
    return g


def power_fit(x, y):
    """Least-squares fit of y = a x^k in log-log.  Returns (a, k)."""
    k, loga = np.polyfit(np.log(np.asarray(x, float)), np.log(np.asarray(y, float)), 1)
    return float(np.exp(loga)), float(k)


# the quantities of a scaling run fitted against the wallette's size, and
# their columns in the scaling table
SCALED = {"wall_time_s": "run_time_s", "us_per_step": "step_time_us", "tets": "tetrahedra"}


def scaling(units, runs, settings):
    """Run time, time per step and tetrahedra against the number of units
    (``units``: the scaling runs' rows with their wallettes' 'courses')
    and against cells per unit edge (the ok runs of the first case in the
    sweep table ``runs`` at the grid ``settings``): one row per run
    (against: 'units' or 'cells', size: the units or the cells along a
    unit's edge, and the quantities, named as SCALED names them), from
    which the caption and the figure fit their power laws (power_fit)."""
    first = runs.case.iloc[0]
    cells = runs[(runs.case == first) & runs.setting.isin(settings) & runs.ok]
    tables = {"units": units, "cells": cells.sort_values("cells_n").assign(cells=lambda t: t.cells_n)}
    rows = []
    for name, t in tables.items():
        t = t.assign(us_per_step=t.wall_time_s / t.steps * 1e6)
        rows.append(pd.DataFrame({"against": name, "size": t[name].to_numpy(),
                                  **{out: t[col].to_numpy() for col, out in SCALED.items()}}))
    return pd.concat(rows, ignore_index=True)


def paired(default, fine):
    """The same samples run with the default and with the fine settings,
    one row per sample and level, columns suffixed _default and _fine."""
    return default.merge(fine, on=["sigma_v_mpa", "sample"], suffixes=("_default", "_fine"))


def compare_subsample(default, fine):
    """Mean and COV of P_max and failure-mode counts of the same samples run
    with the default and the fine settings, per sigma_v (runs that are not
    ok in either are excluded and counted)."""
    m = paired(default, fine)
    rows = []
    for sv, g in m.groupby("sigma_v_mpa"):
        good = g[g.ok_default & g.ok_fine]
        row = dict(sigma_v_mpa=sv, runs=len(good), excluded=int(len(g) - len(good)))
        for s in ("default", "fine"):
            P = good[f"P_max_kN_{s}"]
            row[f"mean_kN_{s}"] = P.mean()
            row[f"cov_{s}"] = P.std(ddof=1) / P.mean()
            row[f"brick_{s}"] = int((good[f"failure_mode_{s}"] == "brick").sum())
            row[f"joint_{s}"] = int((good[f"failure_mode_{s}"] == "joint").sum())
        row["mean_diff"] = row["mean_kN_default"] / row["mean_kN_fine"] - 1.0
        row["cov_diff"] = row["cov_default"] - row["cov_fine"]
        row["same_mode"] = int((good.failure_mode_default == good.failure_mode_fine).sum())
        ratio = good.P_max_kN_default / good.P_max_kN_fine
        row["ratio_mean"], row["ratio_cov"] = ratio.mean(), ratio.std(ddof=1) / ratio.mean()
        rows.append(row)
    return pd.DataFrame(rows)


def sweep_table(rows, cases, path, candidates, tolerance=0.01):
    """The sweep's rows (one per run: case, setting and the run's result)
    with, per case, the error against the converged reference (from the
    settings of the refinement ``path``, accuracy.reference) and whether
    the failure mode is the reference's (that of the finest path run); the
    ``candidates`` flagged.  Returns (table, convergence) where convergence
    has one row per case."""
    t = pd.DataFrame(rows)
    t["cells_n"] = t["cells"].str.split("x").str[0].astype(int)
    t["candidate"] = t["setting"].isin(candidates)
    t["kind"] = np.where(t.candidate, "candidate", np.where(t.setting.isin(path), "path", np.where(
        t.setting == "default", "default", "one-at-a-time")))
    conv = []
    for case in cases:
        c = t[t.case == case]
        runs = c[c.setting.isin(path) & c.ok].sort_values("cells_n")
        ref = reference(runs, tolerance)
        finest = runs.iloc[-1]
        conv.append(dict(case=case, **ref, reference_mode=finest.failure_mode,
                         levels=" ".join(f"{s}:{p:.4g}" for s, p in zip(runs.setting, runs.P_max_kN))))
        t.loc[t.case == case, "error"] = c.P_max_kN / ref["reference_kN"] - 1.0
        t.loc[t.case == case, "mode_ok"] = c.failure_mode == finest.failure_mode
    t["mode_ok"] = t["mode_ok"].astype(bool)
    return t, pd.DataFrame(conv)


def judged_cases(conv):
    """The cases with a converged reference (the others cannot judge a setting)."""
    return list(conv.case[~conv.method.str.startswith("NOT CONVERGED")])


def choose(table, conv, tolerance):
    """Per setting, over the judged cases: the knee among the candidates
    and the defaults beside them (knee False), by cost, with a 'default'
    column."""
    judge = table[table.case.isin(judged_cases(conv))]
    choice = knee(judge[judge.candidate], tolerance)
    default = knee(judge[judge.setting == "default"], tolerance).assign(knee=False)
    choice = pd.concat([choice, default], ignore_index=True).sort_values("total_time_s", kind="stable")
    choice["default"] = choice.setting == "default"
    return choice


# a run's row in runs.csv and references.csv
RUN_COLUMNS = ["P_max_kN", "failure_mode", "ok", "status", "steps", "wall_time_s", "blocks", "cells",
               "subcontact_refine", "tets", "subcontacts", "units"]
# the table's values: written to 17 digits since it holds them; the first
# table (2026-11-27) came from runs.csv, written to 6
CHECK_DIGITS = 6


def check_references(table, fresh):
    """Raise ValueError unless every ``fresh`` row (a path level rerun now:
    case, setting, P_max_kN, steps) equals its row of the references'
    ``table`` to the table's digits, with the same steps: the references
    were made by a solver that computes what today's does."""
    for row in fresh:
        ref = table[(table.case == row["case"]) & (table.setting == row["setting"])]
        if ref.empty:
            raise ValueError(f"results/accuracy/references.csv has no row {row['case']}/{row['setting']}: "
                             "rerun the references (snakemake --cores 2 --forcerun accuracy_references accuracy)")
        p, steps = float(ref.P_max_kN.iloc[0]), int(ref.steps.iloc[0])
        if f"{p:.{CHECK_DIGITS}g}" != f"{row['P_max_kN']:.{CHECK_DIGITS}g}" or steps != int(row["steps"]):
            raise ValueError(f"the references are not today's solver's: {row['case']}/{row['setting']} gives "
                             f"P_max {row['P_max_kN']!r} kN in {row['steps']} steps, the table {p!r} kN in {steps}; "
                             "rerun them (snakemake --cores 2 --forcerun accuracy_references accuracy)")
