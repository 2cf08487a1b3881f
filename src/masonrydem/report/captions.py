"""The numbers in the report's captions.  A caption is a template
(workflow/report/NAME.rst, reStructuredText with str.format fields) that
its rule fills with what it found: each function here takes the rule's
tables and returns the fields of one template (a dict), or of several
(a dict by template name)."""
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis import accuracy
from ..analysis import statistics as A
from ..analysis.fractiles import span


def excluded_detail(runs):
    """The runs left out of the statistics by status: ' (lower_bound: 1,
    diverged: 2)', or '' where none is."""
    bad = runs.status[~runs.ok].value_counts()
    return " (" + ", ".join(f"{k}: {v}" for k, v in bad.items()) + ")" if len(bad) else ""


def write_caption(template, path, **values):
    """A report caption: the text of ``template`` filled with ``values``."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(Path(template).read_text().format(**values))


def write_captions(templates, outputs, values):
    """Captions of one rule: template i (workflow/report/NAME.rst) filled
    with values[NAME] and written to outputs[i]."""
    for t, o in zip(templates, outputs):
        write_caption(t, o, **values.get(Path(t).stem, {}))


def num(x, spec):
    """A number for a caption; an undefined one (the COV of one run) says so."""
    return "undefined" if pd.isna(x) else format(x, spec)


def bullets(lines):
    return "\n".join(f"- {line}" for line in lines)


# --- validation, stability, reduced models, specimens ----------------------------
def validation_summary(table):
    """validation.summary_table's rows."""
    return dict(lines=bullets(
        f"{r.case}, sigma_v = {r.sigma_v_mpa:g} MPa: **P_max {r.P_max_kN:.3f} kN** at {r.disp_at_peak_mm:.3f} mm "
        f"({r.strength_mpa:.3f} MPa, initial stiffness {r.initial_stiffness_kN_per_mm:.1f} kN/mm), "
        f"{r.failure_mode} failure, {r.status}, {r.P_max_change_vs_reference_pct:+.2f} % against the reference"
        for r in table.itertuples()))


def hard_cases(table, limit):
    """validation.hard_cases_table's rows, and how many runs miss their
    expected mode or end without a usable status; ``limit``: the load's
    unbalance below which a peak counts (the solver's)."""
    lines = [f"{r.run}: {r.status}, **P_max {r.P_max_kN:.3f} kN**, {r.failure_mode} failure "
             f"(expected: {r.expect}{'' if r.mode_as_expected else ', NOT MET'}), {r.steps} steps, "
             f"load unbalanced by {r.unbalance_at_peak:.4f} at the peak, post-peak {r.post_peak}"
             + ("" if pd.isna(r.half_rate_change_pct) else f", {r.half_rate_change_pct:+.2f} % against {r.case}")
             for r in table.itertuples()]
    return dict(lines=bullets(lines), n=len(table), unmet=int((~(table.mode_as_expected & table.ok)).sum()),
                limit=f"{limit:g}")


def reduced(table, tolerance):
    """validation.reduced_table's rows, case by case against the full model."""
    lines = []
    for case, g in table.groupby("case", sort=False):
        full = g[g.model == "full"].iloc[0]
        parts = [f"full {full.P_max_kN:.3f} kN ({full.failure_mode}, {full.wall_time_s:.1f} s)"]
        parts += [f"{r.model} {r.P_max_kN:.3f} kN ({r.change_pct:+.1f} %, {r.failure_mode}, {r.speedup:.1f} x faster"
                  f"{', good enough' if r.good_enough else ''})" for r in g[g.model != "full"].itertuples()]
        lines.append(f"{case} (sigma_v {full.sigma_v_mpa:g} MPa, f_tj {full.f_tj_mpa:g} MPa): " + "; ".join(parts))
    good = table[(table.model != "full") & table.good_enough]
    return dict(lines=bullets(lines), tolerance=f"{100 * tolerance:g} %",
                good=", ".join(f"{r.model} on {r.case}" for r in good.itertuples()) or "none")


def specimens(table):
    """validation.specimen_table's rows; triplets against their closed forms."""
    lines = []
    for r in table.itertuples():
        line = (f"{r.case} ({r.test}, sigma_v {r.sigma_v_mpa:g} MPa, f_tj {r.f_tj_mpa:g} MPa): "
                f"P_max {r.P_max_kN:.2f} kN at {r.disp_at_peak_mm:.3f} mm, stress {r.stress_mpa:.3f} MPa, "
                f"{r.failure_mode} failure, {r.status}")
        if r.test == "triplet":
            line += (f"; peak against c + sigma tan phi = {r.peak_closed_form_mpa:.3f} MPa: "
                     f"{100 * r.peak_error:+.1f} %; at the end {r.end_stress_mpa:.3f} MPa against sigma tan phi = "
                     f"{r.residual_closed_form_mpa:.3f} MPa: {100 * r.residual_error:+.1f} %")
        lines.append(line)
    return dict(lines=bullets(lines))


# --- the stochastic study ---------------------------------------------------------
def sampling_check(check, achieved, correlations):
    """sampling.sampling_check's table and the achieved correlation matrix
    (rows and columns in the table's order): each targeted correlation
    (``correlations``: (name, name) -> rho) as achieved, the largest other
    one, and the largest relative deviation of the sample means and COVs
    from their targets."""
    names = list(check.variable)
    others = np.abs(achieved - np.eye(len(names)))
    pairs = []
    for (a, b), rho in correlations.items():
        i, j = names.index(a), names.index(b)
        others[i, j] = others[j, i] = 0.0
        pairs.append(f"{a}-{b} target {rho:g}, achieved **{achieved[i, j]:.3f}**")
    return dict(targets="; ".join(pairs) if pairs else "none targeted", other=others.max(),
                mean_dev=100 * (check.mean_sample / check.mean_target - 1).abs().max(),
                cov_dev=100 * (check.cov_sample / check.cov_target - 1).abs().max())


FIELDS_NOTE = ("  A variant that draws per unit or joint has field means that hardly vary between its samples (each "
               "field is itself a Latin Hypercube over the wallette's units or joints): its P_max follows the local "
               "values, not the field means, and its correlations with them are close to nothing.")


def statistics(runs, stats, corr, inc, level, inputs, report):
    """Captions of the statistics, correlations and increase tables (by
    template name); ``inc`` is analysis.increase from the lowest to the
    highest level of ``runs``; ``inputs``: the random inputs' columns;
    ``report``: pipeline.plan.report_spec (the landing page's)."""
    levels = sorted(runs[level.column].unique())
    n_corr = int(corr.loc[corr["mode"] == "all", "count"].max())
    noise = f"+-{A.correlation_band(n_corr):.2f} for n = {n_corr}" if n_corr > 2 else "undefined for so few runs"

    def spread(variant):
        cov = A.input_spread(runs, variant, inputs)
        return f"{variant}: " + (", ".join(f"{n} {v:.3f}" for n, v in cov.items()) if cov else "none run")

    stat_lines = [f"{r.variant}, {level.text(getattr(r, level.column))}: mean **{r.P_max_mean_kN:.2f} kN** "
                  f"({span(r.P_max_mean_kN_lo, r.P_max_mean_kN_hi, '.2f')}; "
                  f"{r.strength_mean_mpa:.3f} MPa), COV **{num(r.P_max_cov, '.3f')}** "
                  f"({span(r.P_max_cov_lo, r.P_max_cov_hi)}), {r.count} runs, {100 * r.brick_share:.0f} % brick "
                  f"failures ({span(100 * r.brick_share_lo, 100 * r.brick_share_hi, '.0f', ' %')})"
                  for r in stats[stats["mode"] == "all"].itertuples()]
    corr_lines = []
    for r in corr[corr["mode"] == "all"].itertuples():
        vals = {n: getattr(r, n) for n in inputs}
        top = max(vals, key=lambda n: abs(vals[n]) if pd.notna(vals[n]) else -1)
        corr_lines.append(f"{r.variant}, {level.text(getattr(r, level.column))}: {top} ({vals[top]:+.2f}); "
                          + ", ".join(f"{n} {v:+.2f}" for n, v in vals.items()))
    return dict(
        statistics=dict(excluded=int((~runs.ok).sum()), total=len(runs), lines=bullets(stat_lines),
                        excluded_detail=excluded_detail(runs)),
        correlations=dict(lines=bullets(corr_lines), noise=noise, inputs=", ".join(inputs),
                          fields=FIELDS_NOTE if any(d != "wallette" for d in report["draws"].values()) else "",
                          spreads="; ".join(spread(v) for v in sorted(runs.variant.unique()))),
        increase=dict(lines="; ".join(f"{r.variant} {r.mode} **{100 * r.increase:+.0f} %** "
                                      f"({span(100 * r.increase_lo, 100 * r.increase_hi, '+.0f', ' %')})"
                                      for r in inc.dropna(subset=["increase"]).itertuples())
                      + f" (from {levels[0]:g} to {level.text(levels[-1])})"))


def study_figures(runs, stats, corr, sv_scatter, level, inputs, variant):
    """Captions of the study's figures (by template name): the running
    mean's last 20 %, the brick shares, the correlation trends, the
    correlations of the scatter plot's ``variant`` at its level
    ``sv_scatter`` and the drop after the peak per mode at the lowest and
    highest level."""
    scatter_variant = variant
    levels = np.sort(runs[level.column].unique())
    good = runs[runs.ok]
    rm = []
    for (variant, sv), g in good.groupby(["variant", level.column]):
        m = A.running_mean(g.sort_values("sample").P_max_kN)
        tail = m[int(0.8 * len(m)) - 1:]
        se = g.P_max_kN.std(ddof=1) / len(g) ** 0.5 / m[-1]      # standard error of the mean, relative
        rm.append(f"{variant} {level.text(sv)} {100 * (tail.max() - tail.min()) / m[-1]:.1f} % "
                  f"(standard error of the mean {100 * se:.1f} %)")
    share = [f"{v}: " + ", ".join(f"{level.text(getattr(r, level.column))} {100 * r.brick_share:.0f} %"
                                  for r in g.itertuples())
             for v, g in stats[stats["mode"] == "all"].groupby("variant")]
    cva = corr[corr["mode"] == "all"]
    trend = []
    for v, g in cva.groupby("variant"):
        g = g.sort_values(level.column)
        trend.append(f"{v}: " + ", ".join(f"{n} {g[n].iloc[0]:+.2f} to {g[n].iloc[-1]:+.2f}" for n in inputs))
    at = cva[(cva.variant == scatter_variant) & (cva[level.column] == sv_scatter)]
    drops = [f"{v} {level.text(sv)} {mode} {100 * g.drop_after_peak.median():.0f} % ({len(g)} runs)"
             for (v, sv, mode), g in good[good[level.column].isin([levels[0], levels[-1]])].groupby(
                 ["variant", level.column, "failure_mode"])]
    return dict(
        running_mean=dict(lines="; ".join(rm)),
        brick_share=dict(lines="; ".join(share)),
        correlation_vs_sigma=dict(lines="from the lowest to the highest level, " + "; ".join(trend)),
        scatter_deviation=dict(sv=level.text(sv_scatter), level=level.name, variant=scatter_variant,
                               n=int(at["count"].iloc[0]) if len(at) else 0,
                               lines=", ".join(f"{n} {at[n].iloc[0]:+.2f}" for n in inputs) if len(at) else "none"),
        curves_by_mode=dict(lines="; ".join(drops)))


def typical_run(runs, variant, mode, level):
    """The run to picture for a variant and failure mode: at the level where
    the mode is most frequent among the ok runs, the run nearest the
    median P_max of the mode there.  Returns (run, the mode's runs at that
    level), or (None, None) when no run failed in that mode."""
    group = runs[(runs.variant == variant) & (runs.failure_mode == mode) & runs.ok]
    if group.empty:
        return None, None
    sv = group[level.column].value_counts().sort_index().idxmax()
    at = group[group[level.column] == sv]
    return at.iloc[(at.P_max_kN - at.P_max_kN.median()).abs().argmin()], at


def study_pictures(picked, level):
    """The pictured runs: (variant, mode, run, the mode's runs at the run's
    level) as typical_run picks them (run None: no run failed in
    that mode)."""
    lines = []
    for variant, mode, pick, at in picked:
        if pick is None:
            lines.append(f"{variant}, {mode} failure: no run")
            continue
        lines.append(f"{variant}, {mode} failure: sample {pick['sample']} at {level.text(pick[level.column])} "
                     f"(the level with "
                     f"most {mode} failures, {len(at)} of them, median P_max {at.P_max_kN.median():.2f} kN): "
                     f"P_max **{pick.P_max_kN:.2f} kN**, repeated exactly by the rerun")
    return dict(lines=bullets(lines))


def equations(rows, terms, variant):
    """The prediction equations' rows (equations.prediction_equations), of
    the ``terms`` fitted on the runs of ``variant``."""
    lines = []
    for r in rows:
        if r["mode"] == "lower of two":
            lines.append(f"the predictor, {r['equation']} ({r['n']} runs): MAPE **{r['mape_pct']:.1f} %**, "
                         f"failure mode right in **{100 * r['mode_agreement']:.0f} %** of the runs")
        elif "alpha" in r:
            lines.append(f"{r['mode']} failure ({r['n']} runs): **{r['equation']}**, MAPE **{r['mape_pct']:.1f} %** "
                         f"on the runs it was fitted to, **{r['cv_mape_pct']:.1f} %** out of fold; "
                         f"alpha {r['alpha']:.3g}")
        else:
            lines.append(f"{r['mode']} failure ({r['n']} runs): {r['equation']}")
    return dict(lines=bullets(lines), terms=", ".join(terms), variant=variant)


def design_comparison(design, simulated, fitted, resid_sd, n_samples, inputs, variant):
    """The design comparison (validation.design_table) at the simulated
    levels (``simulated``: mean and std of the strength by sigma_v_mpa);
    ``fitted``: the modes with an equation; ``resid_sd``: the predictor's
    residual scatter (MPa); ``n_samples``: the sampled property sets;
    ``inputs``: validation.design_inputs."""
    vertical = "as3700_vertical" in design.columns
    lines = []
    for sv in simulated.index:
        at = {k: float(np.interp(sv, design.iloc[:, 0], design[k])) for k in design.columns}
        rules = (f"AS3700 vertical {at['as3700_vertical']:.3f} MPa" if vertical else
                 f"Lourenco-Gaetani stepped {at['lg_stepped']:.3f} / brick {at['lg_brick']:.3f} MPa; AS3700 stepped "
                 f"{at['as3700_stepped']:.3f} / line {at['as3700_line']:.3f} MPa")
        lines.append(f"{sv:g} MPa: simulated **{simulated.loc[sv, 'mean']:.3f} +- "
                     f"{simulated.loc[sv, 'std']:.3f} MPa**, predicted **{at['prediction']:.3f} +- "
                     f"{at['band_sd']:.3f} MPa** at the mean properties, "
                     f"**{at['mean_over_samples']:.3f} MPa** on average over the samples; {rules}")
    if vertical:
        rules = ("Beside them AS3700's vertical bending at mean values, the bond with the\n"
                 "precompression f_mt + f_d, at most 3 f_mt (its f_mt taken as the joints' tensile bond,\n"
                 "which the flexural bond strength measures); the horizontal-bending rules do not apply\n"
                 "to a plane of failure parallel to the bed joints.")
    else:
        rules = ("Beside them the\n"
                 f"Lourenco-Gaetani lower bounds (stepped: the joints' cohesion, {inputs['c_ratio']:g} times their "
                 "tensile\n"
                 f"bond, times l_o/h_b, with l_o = {1e3 * inputs['l_o']:.0f} mm the overlap of the modelled units "
                 "and h_b =\n"
                 f"{1e3 * inputs['h_b']:.0f} mm their height; brick: half the units' tensile strength) and the "
                 "AS3700 rules at\n"
                 "mean values (its f_mt taken as the joints' tensile bond, which the flexural bond strength\n"
                 "measures; its f_ut as the units' tensile strength, standing for their lateral modulus of\n"
                 "rupture).")
    return dict(f_tu=inputs["ft_units"], f_tj=inputs["ft_joints"], resid=resid_sd, n_samples=n_samples, variant=variant,
                rules=rules, lines=bullets(lines),
                equations=("the joint and brick equations" if len(fitted) == 2 else
                           f"the {fitted[0]} equation alone (too few runs of the other mode)" if fitted
                           else "no equation (too few runs)"))


def paper_comparison(card):
    """The scorecard (validation.paper_comparison): how many published
    figures lie inside our intervals, item by item, and the main offsets."""
    have = card[card.paper_inside.notna()]
    inside = [f"{item}: **{int(g.paper_inside.astype(bool).sum())} of {len(g)}**"      # coefficients together
              for item, g in have.groupby(have.item.str.split(":").str[0], sort=False)]
    means = card[(card.item == "F_max mean (kN)") & (card["mode"] == "all")]
    eq10 = card[card.item.str.startswith("Eq. 10 on our runs")].set_index(["item", "mode"]).ours
    counts = card[card.item.str.startswith("failures")].set_index("mode")
    lines = [f"the paper's value inside our 95 % interval: {'; '.join(inside)}"]
    if len(means):
        lines.append("all-data mean F_max, ours against the paper's: " + ", ".join(
            f"{r.sigma_v_mpa:g} MPa {r.ours:.2f} / {r.paper:.2f} kN (**{r.difference_pct:+.1f} %**)"
            for r in means.itertuples()))
    if "brick" in counts.index:
        b = counts.loc["brick"]
        lines.append(f"brick failures: **{b.ours:.0f}** ({b.ours_lo:.0f} to {b.ours_hi:.0f}) against the paper's "
                     f"{b.paper:.0f}")
    mape, bias = (("Eq. 10 on our runs: MAPE (%)", "lower of two"), ("Eq. 10 on our runs: bias (%)", "lower of two"))
    if mape in eq10.index:
        lines.append(f"the paper's Eq. 10 (lower of its two) on our runs: MAPE **{eq10[mape]:.1f} %**, "
                     f"bias **{eq10[bias]:+.1f} %**")
    offsets = means.difference_pct
    offsets = (f"{offsets.min():+.1f} to {offsets.max():+.1f} %" if len(offsets) else "(no level in common)")
    return dict(lines=bullets(lines), offsets=offsets)


def modelform(table):
    """The model-form summary (validation.modelform_table): per case and
    level, the options that move P_max most, and the mode changes."""
    t = table[table.assumption != "baseline"]
    lines = []
    for (case, sv), g in t.groupby(["case", "sigma_v_mpa"], sort=False):
        base = table[(table["case"] == case) & (table.sigma_v_mpa == sv) & (table.assumption == "baseline")].iloc[0]
        top = g.reindex(g.change_pct.abs().sort_values(ascending=False).index).head(3)
        changed = ", ".join(f"{r.assumption} {r.option}" for r in g[g.mode_changed].itertuples())
        lines.append(f"{case} failure case, {sv:g} MPa (baseline **{base.P_max_kN:.2f} kN**, {base.failure_mode}): "
                     + ", ".join(f"{r.assumption} {r.option} **{r.change_pct:+.1f} %**" for r in top.itertuples())
                     + (f"; mode changed by {changed}" if changed else ""))
    return dict(n_assumptions=t.assumption.nunique(), n_runs=len(table), lines=bullets(lines))


# --- the accuracy study -------------------------------------------------------------
def accuracy_convergence(conv):
    """accuracy.sweep_table's convergence table, one line per case."""
    return dict(lines=bullets(
        f"{r.case}: **{r.reference_kN:.3f} kN** ({r.reference_mode} failure), {r.method}; path "
        f"(setting: P_max kN) {r.levels}; observed orders of consecutive levels {r.orders or 'none'}; "
        f"finest level {100 * r.finest_error:+.2f} % from the reference"
        for r in conv.itertuples()))


def accuracy_choice(table, conv, choice, baselines, tolerance, numerics):
    """The knee and the defaults (accuracy.choose), and each one-at-a-time
    setting's change of P_max (and mode) and run time against the setting
    it varies (``baselines``: the defaults, or the candidate or path level
    it is 'around'), per case."""
    def describe(setting):
        if not (choice.setting == setting).any():
            return f"**{setting}**, not judged (no case has a converged reference)"
        r = choice[choice.setting == setting].iloc[0]
        return (f"**{setting}**, largest error {100 * r.max_abs_error:.2f} %, modes "
                f"{'right' if r.modes_ok else 'WRONG'}, {r.total_time_s:.1f} s")

    oat = []
    runs = table.set_index(["setting", "case"])
    for setting, g in table[table.kind == "one-at-a-time"].groupby("setting", sort=False):
        around = baselines[setting]
        parts = []
        for r in g.itertuples():
            d = runs.loc[(around, r.case)]
            if not r.ok:
                parts.append(f"{r.case} FAILED ({r.status})")
            else:
                parts.append(f"{r.case} {100 * (r.P_max_kN / d.P_max_kN - 1):+.2f} %"
                             + ("" if r.failure_mode == d.failure_mode else f" ({r.failure_mode} failure)")
                             + f" in {r.wall_time_s / d.wall_time_s:.2f} x the time")
        oat.append(f"{setting}" + ("" if around == "default" else f" (against {around})") + ": " + "; ".join(parts))
    judged = accuracy.judged_cases(conv)
    unjudged = sorted(set(conv.case) - set(judged))
    knee = choice.loc[choice.knee, "setting"]
    return dict(cases=", ".join(judged) + (
                    f"; not judged, no converged reference: {', '.join(unjudged)}" if unjudged else ""),
                tolerance=f"{100 * tolerance:g} %",
                knee=describe(knee.iloc[0]) if len(knee) else "NONE within the tolerance",
                numerics=", ".join(numerics) or "the scene's own", default=describe("default"), oat=bullets(oat))


def accuracy_scaling(table, courses):
    """accuracy.scaling's table (a row per run): the power laws of run time
    and time per step fitted against each size, and the wallettes' courses."""
    fits = [f"{name} ~ {against}^{accuracy.power_fit(g['size'], g[col])[1]:.2f}"
            for against, g in table.groupby("against", sort=False)
            for col, name in (("run_time_s", "run time"), ("step_time_us", "time per step"))]
    return dict(courses=", ".join(str(c) for c in courses), fits="; ".join(fits))


def accuracy_subsample(table, fine):
    """accuracy.compare_subsample's table, one line per precompression."""
    lines = [f"{r.sigma_v_mpa:g} MPa, {r.runs} runs ({r.excluded} excluded): mean P_max "
             f"{num(r.mean_kN_default, '.3f')} kN default, {num(r.mean_kN_fine, '.3f')} kN fine "
             f"({num(100 * r.mean_diff, '+.1f')} %); COV {num(r.cov_default, '.3f')} default, "
             f"{num(r.cov_fine, '.3f')} fine; brick failures {r.brick_default} default, {r.brick_fine} fine; "
             f"same mode in {r.same_mode} of {r.runs}; P_max default/fine {num(r.ratio_mean, '.3f')} "
             f"(COV {num(r.ratio_cov, '.3f')})" for r in table.itertuples()]
    return dict(n=int((table.runs + table.excluded).max()), levels=", ".join(f"{v:g}" for v in table.sigma_v_mpa),
                fine=", ".join(fine), lines=bullets(lines))

