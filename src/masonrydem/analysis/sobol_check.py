"""The study's Sobol indices checked on the solver itself: direct
pick-freeze estimates from runs of the real model at one level, beside
the indices the study draws from a surrogate of its 100 runs
(sensitivity.py).

Method:
1. **Design.** Saltelli's scheme on a scrambled Sobol sequence
   (study.copula.pick_freeze, SALib's sobol.sample without second-order
   terms): N base points give the matrices A and B (N x d each) and, for
   each input i, A with its column i taken from B; N (d + 2) points in
   all, in the copula's independent uniforms, mapped to the inputs exactly
   as the study's indices map them (copula.CopulaMap).  Each point is
   one run of the solver, the study's runs' settings at one level.
2. **Indices.** First-order by Saltelli et al. (2010) and total by
   Jansen (1999), SALib's estimators, on the strengths of the runs,
   centred and scaled first as SALib's analysis does (the first-order
   estimator mean(f_B (f_ABi - f_A)) is not invariant to a shift of the
   output: centring takes that error out).
3. **Intervals.** The N base rows (a row: its A, B and d mixed runs)
   resampled with replacement, the estimators again on each resample;
   the 2.5 and 97.5 % percentiles.  They hold the Monte Carlo error of N
   base points, which is the only error of these indices: no surrogate
   stands between them and the model.
4. **Runs without a strength.** A base row with a run that gave no
   strength (its status not ok) is left out whole, so that the remaining
   rows are still pick-freeze pairs; the table counts them.
"""
import numpy as np
import pandas as pd

CONFIDENCE = 0.95


def _estimates(y):
    """(S1, ST) of the outputs y (N x (d + 2): A, the d mixed, B)."""
    from SALib.analyze.sobol import first_order, total_order
    a, b, ab = y[:, 0], y[:, -1], y[:, 1:-1]
    return (np.array([first_order(a, ab[:, j], b) for j in range(ab.shape[1])]),
            np.array([total_order(a, ab[:, j], b) for j in range(ab.shape[1])]))


def direct_indices(y, ok, d, resamples=1000, seed=0, confidence=CONFIDENCE):
    """S1 and ST with their intervals from the strengths ``y`` of the
    design's runs in SALib's order (module docstring), ``ok`` whether each
    run gave one: dict of arrays S1, S1_lo, S1_hi, ST, ST_lo, ST_hi and the
    base rows kept and left out."""
    y, ok = np.asarray(y, float).reshape(-1, d + 2), np.asarray(ok, bool).reshape(-1, d + 2)
    keep = ok.all(axis=1) & np.isfinite(y).all(axis=1)
    y = y[keep]
    y = (y - y.mean()) / y.std()         # centred, as SALib's analysis: the S1 estimator is not shift-invariant
    s1, st = _estimates(y)
    rng = np.random.default_rng(seed)
    draws = np.array([_estimates(y[rng.integers(0, len(y), len(y))]) for _ in range(resamples)])
    lo, hi = np.percentile(draws, [50 * (1 - confidence), 50 * (1 + confidence)], axis=0)
    return dict(S1=s1, S1_lo=lo[0], S1_hi=hi[0], ST=st, ST_lo=lo[1], ST_hi=hi[1], rows=int(keep.sum()),
                left_out=int((~keep).sum()))


def check_table(direct, study, columns):
    """One row per input (``columns``: the runs table's, in the design's
    order): the direct indices and intervals, the study's (``study``: its
    sensitivity table's rows of the variant, level and mode checked,
    indexed by input), whether the study's estimate lies inside the direct
    interval and, where not, by how much (its distance to the nearer end)."""
    rows = []
    for k, col in enumerate(columns):
        row = {"input": col}
        for s in ("S1", "ST"):
            lo, hi, est = direct[f"{s}_lo"][k], direct[f"{s}_hi"][k], direct[s][k]
            theirs = {f"{s}_study{e}": study.at[col, f"{s}{e}"] if col in study.index and f"{s}{e}" in study
                      else np.nan for e in ("", "_lo", "_hi")}
            x = theirs[f"{s}_study"]           # NaN where the study gives no index: neither inside nor off
            row.update({f"{s}_direct": est, f"{s}_direct_lo": lo, f"{s}_direct_hi": hi, **theirs,
                        f"{s}_inside": bool(lo <= x <= hi), f"{s}_off": max(lo - x, x - hi, 0.0) if x == x else x})
        rows.append(row)
    return pd.DataFrame(rows)


def verdict(table):
    """The check's verdict in words: how many of the study's indices lie
    inside the direct intervals, and those that do not, by how much."""
    given = [(r, s) for r in table.to_dict("records") for s in ("S1", "ST") if r[f"{s}_study"] == r[f"{s}_study"]]
    if not given:
        return "the study gives no indices at this level (too few runs, or a surrogate that does not explain them)"
    outside = [f"{r['input']} {s} {r[f'{s}_study']:.3f} against {r[f'{s}_direct_lo']:.3f} to "
               f"{r[f'{s}_direct_hi']:.3f} ({r[f'{s}_off']:.3f} outside)" for r, s in given if not r[f"{s}_inside"]]
    head = f"{len(given) - len(outside)} of the study's {len(given)} indices inside the direct 95 % intervals"
    return head + ("" if not outside else "; outside: " + "; ".join(outside))


def caption_values(table, direct, runs, check, level, study_rows, batches, core_s):
    """The check's caption's numbers: what was run and how long it took
    (its ``batches`` jobs, ``core_s`` seconds of one core in all), one line
    per input (the direct and the study's indices with their intervals)
    and the verdict."""
    def pair(r, s):
        study = (f"study {r[f'{s}_study']:.3f} ({r[f'{s}_study_lo']:.3f} to {r[f'{s}_study_hi']:.3f})"
                 if r[f"{s}_study"] == r[f"{s}_study"] else "no study index")
        return f"{s} direct {r[f'{s}_direct']:.3f} ({r[f'{s}_direct_lo']:.3f} to {r[f'{s}_direct_hi']:.3f}), {study}"
    lines = [f"{r['input']}: {pair(r, 'S1')}; {pair(r, 'ST')}" for r in table.to_dict("records")]
    return dict(variant=check["variant"], level=f"{level.name} = {level.text(float(check['level']))}",
                base=check["base"], runs=len(runs), failed=int((~runs.ok.astype(bool)).sum()), rows=direct["rows"],
                left_out=direct["left_out"], resamples=check["resamples"],
                study_runs=int(study_rows.runs.iloc[0]) if len(study_rows) else 0,
                minutes=f"{core_s / 60:.1f}", batches=batches,
                lines="\n".join(f"- {x}" for x in lines), verdict=verdict(table))
