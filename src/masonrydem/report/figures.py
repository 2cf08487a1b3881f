"""Figures of the study (docs/study.md, 11-14).  Each function writes one PNG."""
import itertools

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..analysis import accuracy  # noqa: E402
from ..analysis import statistics as A  # noqa: E402
from ..analysis.plots import save_figure  # noqa: E402

MODES = {"joint": "tab:blue", "brick": "tab:red"}
# pixels of the 3-D pictures (masonrydem.report.pictures) that go into the report: at
# 1600 x 1000 the six damage pictures took 2.9 MB of the committed report
PICTURE_WINDOW = (1200, 750)
SIGMA_V = r"$\sigma_v$ (MPa)"
P_MAX = r"$P_{max}$ (kN)"
GREEK = {"alpha", "beta", "gamma", "delta", "epsilon", "eta", "theta", "kappa", "lambda", "mu", "nu", "rho", "sigma",
         "tau", "phi", "psi", "omega"}


def symbol(name):
    """An input's name as a mathematical symbol: its first part the letter
    (a Greek one by its name), the rest its subscript: f_tj as $f_{tj}$,
    sigma_v as $\\sigma_{v}$; a name of several letters without a
    subscript stays as written."""
    head, _, sub = name.partition("_")
    letter = f"\\{head}" if head in GREEK else head
    if not sub and len(head) > 1 and head not in GREEK:
        return name
    return f"${letter}" + (f"_{{{sub.replace('_', ',')}}}" if sub else "") + "$"


def axis_label(level):
    """The axis label of a swept level (analysis.Level)."""
    return f"{symbol(level.name)} ({level.unit})" if level.unit else symbol(level.name)


def save(fig, path):
    fig.tight_layout()
    save_figure(fig, path)


def running_mean(runs, path, level):
    """Running mean of P_max against the number of simulations, per variant
    and level (in sample order)."""
    groups = list(runs[runs.ok].groupby("variant"))
    fig, axes = plt.subplots(1, max(len(groups), 1), figsize=(5.5 * max(len(groups), 1), 4), sharey=True,
                             squeeze=False)
    axes = axes[0]
    for ax, (variant, g) in zip(axes, groups):
        for sv, h in g.groupby(level.column):
            h = h.sort_values("sample")
            ax.plot(np.arange(1, len(h) + 1), A.running_mean(h.P_max_kN), label=level.text(sv))
        ax.set_title(variant)
        ax.set_xlabel("number of simulations")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(r"running mean of $P_{max}$ (kN)")
    axes[-1].legend(title=symbol(level.name), fontsize=10, loc="center left",
                    bbox_to_anchor=(1.01, 0.5))
    save(fig, path)


def _with_interval(ax, x, y, lo, hi, fmt, **kw):
    """A line with error bars from its interval (lo, hi)."""
    y, lo, hi = (np.asarray(a, float) for a in (y, lo, hi))
    ax.errorbar(x, y, yerr=[y - lo, hi - y], fmt=fmt, capsize=3, **kw)


def brick_share(stats, path, level):
    """Share of brick failures against the level, both variants, with
    their 95 % intervals."""
    fig, ax = plt.subplots(figsize=(6, 4))
    for variant, g in stats[stats["mode"] == "all"].groupby("variant"):
        _with_interval(ax, g[level.column], 100 * g.brick_share, 100 * g.brick_share_lo, 100 * g.brick_share_hi,
                       "o-", label=variant)
    ax.set_xlabel(axis_label(level))
    ax.set_ylabel("brick failures (%)")
    ax.grid(alpha=0.3)
    ax.legend()
    save(fig, path)


def correlation_vs_sigma(corr, path, level, inputs, names):
    """Pearson correlation of P_max with each input (its column; ``names``:
    column -> the input's name) against the level (all modes), one panel
    per variant."""
    variants = sorted(corr.variant.unique())
    fig, axes = plt.subplots(1, len(variants), figsize=(5.5 * len(variants), 4), sharey=True, squeeze=False)
    for ax, variant in zip(axes[0], variants):
        g = corr[(corr.variant == variant) & (corr["mode"] == "all")]
        x = g[level.column]
        shift = 0.008 * (x.max() - x.min())     # the inputs shifted a little apart, so that the bars stay readable
        for k, name in enumerate(inputs):
            _with_interval(ax, x + shift * (k - (len(inputs) - 1) / 2), g[name], g[f"{name}_lo"], g[f"{name}_hi"],
                           "o-", label=symbol(names[name]))
        ax.set_title(variant)
        ax.set_xlabel(axis_label(level))
        ax.axhline(0, color="k", lw=0.5)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel(r"Pearson correlation with $P_{max}$")
    axes[0][-1].legend()
    save(fig, path)


def scatter_deviation(runs, at, path, level, means, variant, names):
    """P_max against each input's normalised deviation from its mean (the
    mean of its distribution; ``means``: column -> mean; ``names``: column
    -> the input's name) at the level ``at``, coloured by failure mode
    (the runs of ``variant``)."""
    g = runs[runs.ok & (runs.variant == variant) & np.isclose(runs[level.column], at)]
    cols = min(len(means), 2)      # two panels to a row: readable at a report's width
    rows = -(-len(means) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.4 * rows + 0.4), sharey=True, squeeze=False)
    for ax in axes.flat[len(means):]:
        ax.set_visible(False)
    for ax, name in zip(axes.flat, means):
        dev = A.normalised_deviation(g[name], means[name])
        for mode, color in MODES.items():
            sel = (g.failure_mode == mode).to_numpy()
            ax.scatter(dev[sel], g.P_max_kN[sel], s=12, color=color, label=mode)
        ax.set_xlabel(f"({symbol(names[name])} - mean) / mean")
        ax.grid(alpha=0.3)
    for row in axes:
        row[0].set_ylabel(P_MAX)
    axes[0][0].legend()
    fig.suptitle(f"{variant}, {symbol(level.name)} = {level.text(at)}")
    save(fig, path)


def curves_by_mode(runs, curves, levels, path, level):
    """Load-displacement curves grouped by failure mode, per variant and
    level (runs that are ok only)."""
    variants = sorted(runs.variant.unique())
    fig, axes = plt.subplots(len(variants), len(levels), figsize=(5.5 * len(levels), 3.8 * len(variants)),
                             squeeze=False, sharex=True, sharey=True)
    mode = runs[runs.ok].set_index(["variant", level.column, "sample"]).failure_mode
    for i, variant in enumerate(variants):
        for j, sv in enumerate(levels):
            ax = axes[i][j]
            c = curves[(curves.variant == variant) & np.isclose(curves[level.column], sv)]
            for sample, h in c.groupby("sample"):
                if (variant, sv, sample) in mode.index:     # runs that are not ok are left out
                    ax.plot(h.displacement_mm, h.load_kN, color=MODES[mode[(variant, sv, sample)]], lw=0.6,
                            alpha=0.5)
            ax.set_title(f"{variant}, {level.name} = {level.text(sv)}")
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("load-line displacement (mm)")
    for row in axes:
        row[0].set_ylabel("P (kN)")
    axes[0][0].plot([], [], color=MODES["joint"], label="joint failure")
    axes[0][0].plot([], [], color=MODES["brick"], label="brick failure")
    axes[0][0].legend()
    save(fig, path)


def predicted_vs_simulated(fits, path):
    """Per failure mode: the equation's strength against the simulated one
    (left), and the error of the out-of-fold predictions, each run predicted
    by the equation fitted without it (right)."""
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    lo, hi = np.inf, -np.inf
    for mode, (eq, y) in fits.items():
        ax.scatter(y, eq["fitted"], s=10, color=MODES[mode],
                   label=f"{mode}: MAPE {eq['mape']:.1f} % fitted, {eq['cv_mape']:.1f} % out of fold")
        ax2.hist(100 * (eq["cv_predicted"] - y) / y, bins=30, alpha=0.6, color=MODES[mode], label=mode)
        lo, hi = min(lo, y.min()), max(hi, y.max())
    if np.isfinite(lo):
        ax.plot([lo, hi], [lo, hi], "k--", lw=1)
    ax.set_xlabel("simulated strength (MPa)")
    ax.set_ylabel("predicted strength (MPa)")
    ax.legend(fontsize=10)
    ax.grid(alpha=0.3)
    ax2.set_xlabel("out-of-fold prediction error (%)")
    ax2.set_ylabel("runs")
    ax2.legend()
    save(fig, path)


def design_comparison(design, simulated, path, variant, level, fitted):
    """The design table (validation.design_table) against the swept
    precompression ``level`` (analysis.Level): the prediction at mean
    properties with a +-1 SD band, its mean over the sampled properties,
    the Lourenco-Gaetani and AS3700 rules, beside the simulated strengths
    of ``variant`` (``simulated``: mean and std by level).  ``fitted``: the
    modes with an equation; the prediction's label names them (the lower of
    two, or the one fitted alone), and without any no prediction is drawn."""
    levels = design.iloc[:, 0]
    pred, band = design.prediction, design.band_sd
    fig, ax = plt.subplots(figsize=(10, 4.5))
    if fitted:
        ax.plot(levels, pred, "k-", lw=2, label="prediction at mean properties " + (
            "(lower of the joint and brick equations)" if len(fitted) == 2 else
            f"({fitted[0]} equation alone: too few runs failed otherwise to fit the other)"))
        ax.fill_between(levels, pred - band, pred + band, color="k", alpha=0.15,
                        label="+- 1 SD of the prediction over the samples")
        ax.plot(levels, design.mean_over_samples, "k--", lw=1.2, label="mean of the prediction over the samples")
    if "as3700_vertical" in design:         # vertical bending: its own rule
        ax.plot(levels, design.as3700_vertical, ":", color="tab:blue", lw=2, label="AS3700 vertical: f_mt + f_d, <= 3 f_mt")
    else:
        ax.plot(levels, design.lg_stepped, "--", color="tab:blue", label="Lourenco-Gaetani stepped")
        ax.plot(levels, design.lg_brick, "--", color="tab:red", label="Lourenco-Gaetani brick")
        ax.plot(levels, design.as3700_stepped, ":", color="tab:blue", lw=2, label="AS3700 stepped")
        ax.plot(levels, design.as3700_line, ":", color="tab:red", lw=2, label="AS3700 line")
    ax.errorbar(simulated.index, simulated["mean"], yerr=simulated["std"], fmt="o", color="tab:green", capsize=3,
                label=f"simulated mean +- 1 SD ({variant})")
    ax.set_xlabel(axis_label(level))
    ax.set_ylabel("strength (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=10, loc="center left", bbox_to_anchor=(1.01, 0.5))
    save(fig, path)


def accuracy_pareto(table, conv, choice, tolerance, path):
    """Per case (a panel each, two to a row, the legend in a panel of its
    own): |error| of P_max against run time for every setting; the
    candidates coloured by block model, the refinement path black, the
    one-at-a-time variations grey; the Pareto front, the tolerance, the knee
    and the defaults marked.  Only the front's settings are named (runs.csv
    names every point), where the front has moved on by a factor 1.6 in run
    time."""
    cases = list(conv.case)
    rows = -(-(len(cases) + 1) // 2)
    fig, axes = plt.subplots(rows, 2, figsize=(10, 4.1 * rows), squeeze=False)
    knee = choice.loc[choice.knee, "setting"]
    knee = knee.iloc[0] if len(knee) else None
    handles = {}
    for ax, case in zip(axes.flat, cases):
        _pareto_panel(ax, table[table.case == case], conv[conv.case == case].iloc[0], knee, tolerance)
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    for ax in axes.flat[len(cases):]:
        ax.axis("off")
    axes.flat[len(cases)].legend(handles.values(), handles.keys(), loc="center", fontsize=10,
                                 title="|P_max error| against the converged reference")
    save(fig, path)


def _pareto_panel(ax, runs, ref, knee, tolerance):
    """One case's panel of ``accuracy_pareto`` (``runs``: its rows of
    runs.csv; ``ref``: its row of convergence.csv)."""
    from ..analysis.accuracy import pareto_front
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    c = runs[runs.ok].copy()
    c["abs_err"] = 100 * c.error.abs().clip(lower=1e-5)      # the reference itself (error 0) on the floor
    groups = [(f"candidates: {m}", g) for m, g in c[c.kind == "candidate"].groupby("blocks")]
    for k, (label, g) in enumerate(groups + [("refinement path", c[c.kind == "path"])]):
        ax.scatter(g.wall_time_s, g.abs_err, color=colors[k] if label != "refinement path" else "k", label=label,
                   s=18, zorder=3)
    o = c[c.kind == "one-at-a-time"]
    ax.scatter(o.wall_time_s, o.abs_err, color="0.6", marker="s", s=12, label="one-at-a-time", zorder=2)
    front = c.iloc[pareto_front(c.wall_time_s, c.abs_err)]
    ax.step(front.wall_time_s, front.abs_err, where="post", color="k", lw=0.8, label="Pareto front")
    last = 0.0
    middle = np.sqrt(c.wall_time_s.min() * c.wall_time_s.max()) if len(c) else 1.0
    for k, (_, row) in enumerate(front.iterrows()):
        if row.wall_time_s >= 1.6 * last:       # a name where the front has moved on (no pile-up)
            right = bool(row.wall_time_s > middle)      # named towards the panel's middle, inside it
            ax.annotate(row.setting, (row.wall_time_s, row.abs_err), fontsize=10, xytext=(-4 if right else 4, -10 if
                        k % 2 else 3), textcoords="offset points", ha=("left", "right")[right], annotation_clip=True)
            last = row.wall_time_s
    bad = c[~c.mode_ok]
    ax.scatter(bad.wall_time_s, bad.abs_err, facecolor="none", edgecolor="r", s=90, label="wrong failure mode")
    d = c[c.setting == "default"]
    ax.scatter(d.wall_time_s, d.abs_err, marker="*", s=170, color="gold", edgecolor="k", label="defaults", zorder=4)
    if knee is not None:
        kn = c[c.setting == knee]
        ax.scatter(kn.wall_time_s, kn.abs_err, marker="D", s=70, facecolor="none", edgecolor="k",
                   label=f"knee ({knee})", zorder=5)
    failed = runs[~runs.ok]
    if len(failed):
        top = 1.5 * max(c.abs_err.max(), 100 * tolerance) if len(c) else 100.0
        ax.scatter(failed.wall_time_s, np.full(len(failed), top), marker="x", color="r",
                   label="failed (status in runs.csv)")
    ax.axhline(100 * tolerance, color="k", ls="--", lw=0.8, label=f"tolerance {100 * tolerance:g} %")
    flag = " NOT CONVERGED" if ref.method.startswith("NOT CONVERGED") else ""
    ax.set_title(f"{ref.case}: reference {ref.reference_kN:.2f} kN ({ref.reference_mode}){flag}", fontsize=10)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("run time (s, one core)")
    ax.set_ylabel("|P_max error| (%)")
    ax.grid(alpha=0.3, which="both")


def accuracy_scaling(table, path):
    """Run time (s) and time per step (ms) against the number of units and
    against cells per unit edge (log-log), each with its fitted power law:
    from the table accuracy.scaling writes (scaling.csv, a row per run)."""
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex="col")
    quantities = (("run_time_s", 1.0, "run time (s)"), ("step_time_us", 1e3, "time per step (ms)"))
    for j, (against, xlabel) in enumerate((("units", "units in the wallette"), ("cells", "cells along a unit"))):
        for i, (col, per, ylabel) in enumerate(quantities):
            ax = axes[i][j]
            rows = table[table.against == against]
            x, y = rows["size"].to_numpy(float), rows[col].to_numpy(float)
            a, k = accuracy.power_fit(x, y)
            ax.loglog(x, y / per, "o", color="C0" if i == 0 else "C1")
            xs = np.geomspace(x.min(), x.max(), 20)
            ax.loglog(xs, a * xs ** k / per, "k:", lw=0.8, label=f"fit: exponent {k:.2f}")
            ax.set_ylabel(ylabel)
            ax.grid(alpha=0.3, which="both")
            ax.legend(fontsize=10)
            ax.set_xticks(x, [f"{v:g}" for v in x], minor=False)
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            plain = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
            ax.yaxis.set_major_formatter(plain)
            ax.yaxis.set_minor_formatter(matplotlib.ticker.FuncFormatter(
                lambda v, _: f"{v:g}" if round(v / 10 ** np.floor(np.log10(v))) in (2, 3, 5) else ""))
        axes[1][j].set_xlabel(xlabel)
    save(fig, path)


def accuracy_subsample(paired, path):
    """P_max of the same samples at default against fine settings
    (accuracy.paired; runs ok in both), by precompression; the marker says
    whether the failure mode agrees."""
    merged = paired[paired.ok_default & paired.ok_fine]
    fig, ax = plt.subplots(figsize=(5.5, 5))
    for sv, g in merged.groupby("sigma_v_mpa"):
        same = g.failure_mode_default == g.failure_mode_fine
        line = ax.scatter(g.P_max_kN_fine[same], g.P_max_kN_default[same], label=f"{sv:g} MPa")
        ax.scatter(g.P_max_kN_fine[~same], g.P_max_kN_default[~same], marker="x", color=line.get_facecolor(),
                   label=f"{sv:g} MPa, mode differs")
    lim = [0, 1.05 * max(merged.P_max_kN_fine.max(), merged.P_max_kN_default.max())]
    ax.plot(lim, lim, "k-", lw=0.8)
    ax.set_xlim(lim)
    ax.set_ylim(lim)
    ax.set_xlabel("P_max, fine settings (kN)")
    ax.set_ylabel("P_max, default settings (kN)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=10)
    save(fig, path)


def placeholder(text, path):
    """A picture that says why there is none (the words wrapped to its width)."""
    import textwrap
    fig, ax = plt.subplots(figsize=(8, 2))
    ax.axis("off")
    ax.text(0.5, 0.5, textwrap.fill(text, 90), ha="center", va="center")
    save_figure(fig, path)


def paper_comparison(card, path):
    """The scorecard's F_max means and COVs against precompression, per
    failure mode: ours with their 95 % intervals, the paper's as crosses."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    colours = {"all": "k", **MODES}
    for ax, item in zip(axes, ("F_max mean (kN)", "F_max COV")):
        for mode, g in card[card.item == item].groupby("mode"):
            _with_interval(ax, g.sigma_v_mpa, g.ours, g.ours_lo, g.ours_hi, "o-", color=colours[mode],
                           label=f"{mode}: ours")
            ax.plot(g.sigma_v_mpa, g.paper, "x--", color=colours[mode], ms=9, label=f"{mode}: paper")
        ax.set_xlabel(SIGMA_V)
        ax.set_ylabel({"F_max mean (kN)": r"mean $F_{max}$ (kN)", "F_max COV": r"COV of $F_{max}$"}[item])
        ax.grid(alpha=0.3)
    axes[-1].legend(fontsize=10, loc="center left", bbox_to_anchor=(1.01, 0.5))
    save(fig, path)


def tornado(table, path, titles=None):
    """The model-form study: per case (columns) and level (rows), each
    assumption's options as bars of the change of P_max (%), each named at
    its end, the assumptions sorted by their largest change; an option that
    changed the failure mode hatched.  ``titles``: an assumption's name ->
    how the chart names it (the study's config; else its name's words)."""
    from matplotlib.patches import Patch
    t = table[table.assumption != "baseline"]
    order = t.groupby("assumption").change_pct.apply(lambda c: c.abs().max()).sort_values().index
    cases, levels = list(dict.fromkeys(t["case"])), sorted(t.sigma_v_mpa.unique())
    fig, axes = plt.subplots(len(levels), len(cases), figsize=(5 * len(cases) + 1.5, len(order) * len(levels) / 2 + 2),
                             sharey=True, sharex=True, squeeze=False)
    for (j, case), (i, sv) in itertools.product(enumerate(cases), enumerate(levels)):
        ax, g = axes[i, j], t[(t["case"] == case) & (t.sigma_v_mpa == sv)]
        for y, name in enumerate(order):
            opts = g[g.assumption == name]
            for k, r in enumerate(opts.itertuples()):
                yy = y + (k - (len(opts) - 1) / 2) * 0.4
                ax.barh(yy, r.change_pct, height=0.38, color="tab:red" if r.change_pct > 0 else "tab:blue",
                        hatch="//" if r.mode_changed else None, edgecolor="k", lw=0.3)
                ax.text(r.change_pct + (1 if r.change_pct >= 0 else -1), yy, r.option, fontsize=10, va="center",
                        ha="left" if r.change_pct >= 0 else "right")
        ax.axvline(0, color="k", lw=0.8)
        ax.set_yticks(range(len(order)), [(titles or {}).get(n, n.replace("_", " ")) for n in order], fontsize=10)
        ax.set_title(f"{case} failure case, " + r"$\sigma_v$" + f" = {sv:g} MPa", fontsize=10)
        ax.grid(axis="x", alpha=0.3)
        ax.tick_params(labelbottom=True)          # every panel its scale
        ax.set_xlabel(r"change of $P_{max}$ against the baseline (%)")
    lo, hi = t.change_pct.min(), t.change_pct.max()
    axes[0, 0].set_xlim(lo - 0.45 * (hi - lo), hi + 0.45 * (hi - lo))     # room for the options' names
    fig.legend(handles=[Patch(color="tab:red", label=r"$P_{max}$ higher"), Patch(color="tab:blue", label=r"$P_{max}$ lower"),
                        Patch(facecolor="w", edgecolor="k", hatch="//", label="failure mode changed")],
               loc="upper center", ncol=3, frameon=False, bbox_to_anchor=(0.5, 1.0))
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.5 / fig.get_figheight()))
    save_figure(fig, path, dpi=70)

