"""Both bending directions in the report (analysis/directions.py): the
directions table's caption, the user's wallette tests in words, and the
figure of f_x1, f_x2 and mu per level."""
from . import captions, figures


def caption(table, level, mortar, mean, runs_own, runs_other, study):
    """Both directions' caption (analysis.directions.with_codes): per
    variant and level f_x1, f_x2 and mu with their intervals and the
    simulated-to-code ratios."""
    lines = []
    for r in table.itertuples(index=False):
        at = level.text(getattr(r, level.column))
        lines.append(f"{r.variant}, {at}: f_x1 **{r.f_x1_mpa:.3f} MPa** ({r.f_x1_low:.3f} to {r.f_x1_high:.3f}), "
                     f"f_x2 **{r.f_x2_mpa:.3f} MPa** ({r.f_x2_low:.3f} to {r.f_x2_high:.3f}), mu **{r.mu:.3f}** "
                     f"({r.mu_low:.3f} to {r.mu_high:.3f}; pairs' correlation {r.pair_correlation:.2f}); "
                     f"characteristic f_x1 {r.f_x1_k_mpa:.3f} / EN f_xk1 + sigma_d {r.en_fxk1_app_mpa:.3f} = "
                     f"{r.f_x1_k_over_en:.2f}, f_x2 {r.f_x2_k_mpa:.3f} / EN f_xk2 {r.en_fxk2_mpa:.3f} = "
                     f"{r.f_x2_k_over_en:.2f}; mean f_x1 / AS 3700 vertical {r.as3700_vertical_mpa:.3f} = "
                     f"{r.f_x1_over_as3700:.2f}, mean f_x2 / AS 3700 horizontal {r.as3700_horizontal_mpa:.3f} = "
                     f"{r.f_x2_over_as3700:.2f}")
    return dict(study=study, pairs=int(table.pairs.max()) if len(table) else 0, runs_own=runs_own,
                runs_other=runs_other, f_tj=mean["ft_joints"], f_tu=mean["ft_units"], mortar=mortar,
                lines=captions.bullets(lines))


def tests_words(tested, agreement, sheet, variant, level):
    """The user's wallette tests in the prediction: each test's percentile
    among the runs of its direction and level, and the exact test of their
    agreement (analysis.directions.agreement) in words."""
    u, mean, p = agreement
    lines = [f"test row {r.row}, {r.direction}, {level.text(getattr(r, level.column))}: "
             f"**{r.strength_mpa:.3f} MPa**, above {r.runs_below:g} of {r.runs} runs (mean "
             f"{r.simulated_mean_mpa:.3f} MPa): predicted percentile **{100 * r.percentile:.0f} %**"
             for r in tested.itertuples(index=False)]
    verdict = ("they agree with the prediction at the 5 % level" if p > 0.05 else
               "they disagree with the prediction at the 5 % level: the model, fed by the component tests, "
               f"predicts them {'too low' if u > mean else 'too high'}")
    return (f"The user's own wallette tests ({sheet}), each placed among the {variant} runs of its direction "
            f"and level (ties count half):\n\n" + captions.bullets(lines) + "\n\nTheir agreement, an exact stratified "
            f"Mann-Whitney test (under the prediction each test is one more draw of its direction's and level's "
            f"distribution): runs below the tests {u:g} against {mean:g} expected, two-sided **p = {p:.3f}**: "
            f"{verdict}.  With a handful of tests it finds only large misses (its power: docs/lab-to-design.md, 11).")


def figure(table, level, path, tested=None):
    """Both directions per level (analysis.directions.with_codes): f_x1 and
    f_x2 with their 95 % intervals and the codes beside them (left), mu
    with Fieller's interval (right); a variant a marker each; the user's
    wallette tests (analysis.directions.placed) as crosses."""
    fig, (ax, axm) = figures.plt.subplots(1, 2, figsize=(11, 4.2))
    for direction, color, name in (("vertical", "tab:blue", "f_x1"), ("horizontal", "tab:red", "f_x2")):
        t = tested[tested.direction == direction] if tested is not None and len(tested) else []
        if len(t):
            ax.plot(t[level.column], t.strength_mpa, "x", color=color, ms=8, label=f"your {name} tests")
    for k, (variant, g) in enumerate(table.groupby("variant", sort=False)):
        x = g[level.column].to_numpy(float)
        for name, color in (("f_x2", "tab:red"), ("f_x1", "tab:blue")):
            m = g[f"{name}_mpa"]
            ax.errorbar(x, m, yerr=[m - g[f"{name}_low"], g[f"{name}_high"] - m], fmt="os^"[k % 3], color=color,
                        capsize=3, label=f"{name} mean, 95 % interval ({variant})")
        axm.errorbar(x, g.mu, yerr=[g.mu - g.mu_low, g.mu_high - g.mu], fmt="os^"[k % 3], color="k", capsize=3,
                     label=f"mu = f_x1 / f_x2 ({variant})")
        if k == 0:
            ax.plot(x, g.en_fxk1_app_mpa, ":", color="tab:blue", label="EN 1996-1-1 f_xk1 + sigma_d")
            ax.plot(x, g.en_fxk2_mpa, ":", color="tab:red", label="EN 1996-1-1 f_xk2")
            ax.plot(x, g.as3700_vertical_mpa, "--", color="tab:blue", label="AS 3700 vertical (mean values)")
            ax.plot(x, g.as3700_horizontal_mpa, "--", color="tab:red", label="AS 3700 horizontal (mean values)")
            axm.plot(x, g.en_fxk1_app_mpa / g.en_fxk2_mpa, ":", color="tab:gray",
                     label="EN 1996-1-1 (f_xk1 + sigma_d) / f_xk2")
    for a, ylabel in ((ax, "flexural strength (MPa)"), (axm, "orthogonal ratio mu")):
        a.set_xlabel(figures.axis_label(level))
        a.set_ylabel(ylabel)
        a.grid(alpha=0.3)
        a.legend(fontsize=10)
    figures.save(fig, path)
