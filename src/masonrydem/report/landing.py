"""The report's landing page (workflow/report/workflow.rst): what was run,
how, what it found in numbers, and how it compares with the source paper
(each published mean inside our 95 % interval or not, and inside the
model-form band or not).  Every number comes from the study's tables."""
import numpy as np
import pandas as pd
import yaml

from .captions import excluded_detail, num


def modelform_band(summary):
    """The model-form study's band (results/modelform/summary.csv): per
    case and level, the smallest and largest change of P_max (%) over the
    options of every assumption, as {case: {level: [lo, hi]}}."""
    t = summary[summary.assumption != "baseline"]
    return {case: {float(sv): [float(g.change_pct.min()), float(g.change_pct.max())]
                   for sv, g in c.groupby("sigma_v_mpa")} for case, c in t.groupby("case")}


def band_at(band, mode, sv):
    """The band's change (lo, hi, %) for a failure mode ('all': every case)
    at a level: the level's own, or the envelope of the levels on either
    side of it."""
    cases = [band[mode]] if mode in band else list(band.values())
    lo, hi = [], []
    for levels in cases:
        at = sorted(float(x) for x in levels)
        near = [x for x in at if np.isclose(x, sv)] or \
            [max([x for x in at if x < sv], default=at[0]), min([x for x in at if x > sv], default=at[-1])]
        lo += [levels[x][0] for x in near]
        hi += [levels[x][1] for x in near]
    return min(lo), max(hi)


def paper_means(card, band):
    """The published mean F_max per failure mode and level beside ours:
    our mean with its 95 % interval, whether the paper's lies inside it,
    and our mean moved by the model-form band (None: no band)."""
    means = card[card.item == "F_max mean (kN)"].copy()
    if band:
        moved = [band_at(band, r.mode, r.sigma_v_mpa) for r in means.itertuples()]
        means["band_lo"] = [r.ours * (1 + lo / 100) for r, (lo, _) in zip(means.itertuples(), moved)]
        means["band_hi"] = [r.ours * (1 + hi / 100) for r, (_, hi) in zip(means.itertuples(), moved)]
        means["in_band"] = (means.paper >= means.band_lo) & (means.paper <= means.band_hi)
    return means


def _yes(x):
    return "yes" if x else "**no**"


def paper_findings(card, band):
    """The landing page's comparison with the paper: a table of the
    all-data means and counts over every mode and level."""
    if card is None:
        return "No source paper is compared (config study.paper)."
    means = paper_means(card, band)
    rows = [(f"{r.sigma_v_mpa:g}", f"{r.paper:.2f}", f"{r.ours:.2f} ({r.ours_lo:.2f} to {r.ours_hi:.2f})",
             f"{r.difference_pct:+.1f}", _yes(r.paper_inside))
            + ((f"{r.band_lo:.1f} to {r.band_hi:.1f}", _yes(r.in_band)) if band else ())
            for r in means[means["mode"] == "all"].itertuples()]
    head = ("sigma_v (MPa)", "paper (kN)", "ours, 95 % interval (kN)", "ours - paper (%)", "paper inside interval") \
        + (("model-form band (kN)", "paper inside band") if band else ())
    inside = int(means.paper_inside.astype(bool).sum())
    text = [f"The source paper's mean F_max lies inside our 95 % interval for **{inside} of {len(means)}** failure "
            f"modes and levels"]
    if band:
        text.append(f" and inside the model-form band (our mean moved by the smallest and largest change of any "
                    f"modelling option: `Model form`_) for **{int(means.in_band.sum())} of {len(means)}**")
    cov = card[card.item == "F_max COV"]
    text.append(f"; its COV inside our interval for {int(cov.paper_inside.astype(bool).sum())} of {len(cov)}.  "
                f"All modes together:")
    return "".join(text) + "\n\n" + _rst_table(head, rows)


def in_short(stats, level):
    """The landing page's finding in one sentence: the first variant's mean
    P_max, COV and share of brick failures at its lowest and highest
    level (all failure modes together)."""
    s = stats[(stats["mode"] == "all") & (stats.variant == stats.variant.iloc[0])].sort_values(level.column)
    lo, hi = s.iloc[0], s.iloc[-1]
    at = lambda r: f"{r[level.column]:g} {level.unit}".rstrip()  # noqa: E731
    if len(s) == 1:
        return (f"The mean P_max is {lo.P_max_mean_kN:.2f} kN with a COV of {lo.P_max_cov:.2f}, "
                f"{100 * lo.brick_share:.0f} % of the runs failing through the units (variant {lo.variant}).")
    change = 100 * (hi.P_max_mean_kN / lo.P_max_mean_kN - 1)
    return (f"From {at(lo)} to {at(hi)} of {level.name} the mean P_max goes from {lo.P_max_mean_kN:.2f} to "
            f"{hi.P_max_mean_kN:.2f} kN ({change:+.0f} %), its COV from {lo.P_max_cov:.2f} to {hi.P_max_cov:.2f}, "
            f"and the share of runs failing through the units from {100 * lo.brick_share:.0f} to "
            f"{100 * hi.brick_share:.0f} % (variant {lo.variant}).")


def paper_in_short(card):
    """The comparison with the paper in one sentence: our all-modes mean's
    offset from the paper's over the levels, and how many of the paper's
    means and COVs lie inside our 95 % intervals."""
    if card is None:
        return "No source paper is compared."
    means, cov = card[card.item == "F_max mean (kN)"], card[card.item == "F_max COV"]
    d = means[means["mode"] == "all"].difference_pct
    return (f"Our mean P_max of all failure modes stands {d.min():+.1f} to {d.max():+.1f} % from the paper's at "
            f"its {len(d)} levels; the paper's means lie inside our 95 % intervals for "
            f"{int(means.paper_inside.astype(bool).sum())} of {len(means)} failure modes and levels, its COVs "
            f"for {int(cov.paper_inside.astype(bool).sum())} of {len(cov)}.")


def _rst_table(head, rows):
    widths = [max(len(x) for x in col) for col in zip(head, *rows)]
    rule = "  ".join("=" * w for w in widths)
    line = lambda cells: "  ".join(c.ljust(w) for c, w in zip(cells, widths)).rstrip()  # noqa: E731
    return "\n".join([rule, line(head), rule, *map(line, rows), rule])


# the test a vertical study runs, in the landing page's words
VERTICAL = "four-point out-of-plane vertical bending (the plane of failure parallel to the bed joints)"


def landing(runs, stats, excluded, level, report, source, card=None, band=None, direction="horizontal"):
    """The fields of the landing page: what was run, how, the study's key
    table (mean P_max, COV, brick share per variant and level), the
    comparison with the paper (``card``: the scorecard; ``band``:
    modelform_band, or None); ``report``: pipeline.plan.report_spec;
    ``source``: the study's source (source); ``direction``: the study's
    bending direction."""
    rows = [(r.variant, f"{getattr(r, level.column):g}", f"{r.P_max_mean_kN:.2f}", f"{r.strength_mean_mpa:.3f}",
             num(r.P_max_cov, ".3f"), f"{100 * r.brick_share:.0f}", str(r.count))
            for r in stats[stats["mode"] == "all"].itertuples()]
    head = ("variant", f"{level.name} ({level.unit})".replace(" ()", ""), "mean P_max (kN)", "strength (MPa)", "COV",
            "brick (%)", "runs")
    levels = sorted(runs[level.column].unique())

    def one(col):
        vals = runs[col].dropna().astype(str).unique() if col in runs else []
        return ", ".join(vals) if len(vals) else "not recorded"

    variants, n_var = "; ".join(f"{n}: {what}" for n, what in report["variants"].items()), runs.variant.nunique()
    links = "\n".join(f"- {name if name.isalnum() else f'`{name}`'}_: {what}." for name, what in report["categories"])
    accuracy = any(name == "Accuracy" for name, _ in report["categories"])
    title = f"masonrydem: the {report['study']} study, a wallette in {direction} bending"
    return dict(title=title, rule="=" * len(title), found=in_short(stats, level), verdict=paper_in_short(card),
                scene=report["scene"], wallette=report["wallette"], source=source,
                test=VERTICAL if direction == "vertical" else report["test"],
                under=" under vertical precompression" if report["precompression"] else "",
                inputs=f"its {len(report['inputs'])} random input{'s' if len(report['inputs']) > 1 else ''} "
                       f"({', '.join(report['inputs'])})",
                variant_list=variants, links=links,
                accuracy=" (Accuracy_ compares them with finer settings)" if accuracy else "",
                total=len(runs), variants=f"{n_var} variant{'s' * (n_var != 1)}", n_samples=runs["sample"].nunique(),
                n_levels=len(levels), level=level.name,
                levels=f"{', '.join(f'{x:g}' for x in levels)} {level.unit}".rstrip(),
                blocks=one("blocks"), cells=one("cells"), refine=one("subcontact_refine"),
                solver=one("solver_version"), excluded=excluded, excluded_detail=excluded_detail(runs),
                cpu=_core_time(float(np.sum(runs.get("wall_time_s", np.nan) / runs.get("lanes", 1)))),
                table=_rst_table(head, rows), paper=paper_findings(card, band))


def _core_time(seconds):
    """A summed run time in core-hours, or core-minutes below one hour."""
    return f"{seconds / 3600:.1f} core-hours" if seconds >= 3600 else f"{seconds / 60:.1f} core-minutes"


def source(paper, study_file):
    """The landing page's source: the study's source paper as its
    published figures' file ``paper`` (config study.paper) cites it, or,
    with none, the study file."""
    if paper:
        with open(paper) as f:
            return f"{yaml.safe_load(f)['source']}; its published figures: ``{paper}``."
    return f"the study file ``{study_file}``."


def read_card(path):
    """The scorecard (results/study/paper_comparison.csv), or None."""
    return pd.read_csv(path) if path else None
