"""Figures of the study (study.md, 6).  Each function writes one PNG."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import analysis as A  # noqa: E402

MODES = {"joint": "tab:blue", "brick": "tab:red"}


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def running_mean(runs, path):
    """Running mean of P_max against the number of simulations, per variant
    and precompression (in sample order)."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    for ax, (variant, g) in zip(axes, runs[runs.ok].groupby("variant")):
        for sv, h in g.groupby("sigma_v_mpa"):
            h = h.sort_values("sample")
            ax.plot(np.arange(1, len(h) + 1), A.running_mean(h.P_max_kN), label=f"{sv:g} MPa")
        ax.set_title(variant)
        ax.set_xlabel("number of simulations")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("running mean of P_max (kN)")
    axes[-1].legend(title="sigma_v")
    _save(fig, path)


def brick_share(stats, path):
    """Share of brick failures against precompression, both variants."""
    fig, ax = plt.subplots(figsize=(6, 4))
    for variant, g in stats[stats["mode"] == "all"].groupby("variant"):
        ax.plot(g.sigma_v_mpa, 100 * g.brick_share, "o-", label=variant)
    ax.set_xlabel("sigma_v (MPa)")
    ax.set_ylabel("brick failures (%)")
    ax.grid(alpha=0.3)
    ax.legend()
    _save(fig, path)


def correlation_vs_sigma(corr, path):
    """Pearson correlation of P_max with each input against precompression
    (all modes), one panel per variant."""
    variants = sorted(corr.variant.unique())
    fig, axes = plt.subplots(1, len(variants), figsize=(5.5 * len(variants), 4), sharey=True, squeeze=False)
    for ax, variant in zip(axes[0], variants):
        g = corr[(corr.variant == variant) & (corr["mode"] == "all")]
        for name in A.INPUTS:
            ax.plot(g.sigma_v_mpa, g[name], "o-", label=name)
        ax.set_title(variant)
        ax.set_xlabel("sigma_v (MPa)")
        ax.axhline(0, color="k", lw=0.5)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("Pearson correlation with P_max")
    axes[0][-1].legend()
    _save(fig, path)


def scatter_deviation(runs, sigma_v, path):
    """P_max against each input's normalised deviation from its mean at one
    precompression, coloured by failure mode (non-spatial variant)."""
    g = runs[runs.ok & (runs.variant == "nonspatial") & np.isclose(runs.sigma_v_mpa, sigma_v)]
    fig, axes = plt.subplots(1, len(A.INPUTS), figsize=(4 * len(A.INPUTS), 3.6), sharey=True)
    for ax, name in zip(axes, A.INPUTS):
        dev = A.normalised_deviation(g[name]) if len(g) else np.array([])
        for mode, color in MODES.items():
            sel = (g.failure_mode == mode).to_numpy()
            ax.scatter(dev[sel], g.P_max_kN[sel], s=12, color=color, label=mode)
        ax.set_xlabel(f"({name} - mean) / mean")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("P_max (kN)")
    axes[0].legend()
    fig.suptitle(f"non-spatial, sigma_v = {sigma_v:g} MPa")
    _save(fig, path)


def curves_by_mode(runs, curves, levels, path):
    """Load-displacement curves grouped by failure mode, per variant and
    precompression level."""
    variants = sorted(runs.variant.unique())
    fig, axes = plt.subplots(len(variants), len(levels), figsize=(5.5 * len(levels), 3.8 * len(variants)),
                             squeeze=False, sharex=True, sharey=True)
    mode = runs.set_index(["variant", "sigma_v_mpa", "sample"]).failure_mode
    for i, variant in enumerate(variants):
        for j, sv in enumerate(levels):
            ax = axes[i][j]
            c = curves[(curves.variant == variant) & np.isclose(curves.sigma_v_mpa, sv)]
            for sample, h in c.groupby("sample"):
                m = mode.get((variant, sv, sample), "joint")
                ax.plot(h.displacement_mm, h.load_kN, color=MODES.get(m, "k"), lw=0.6, alpha=0.5)
            ax.set_title(f"{variant}, sigma_v = {sv:g} MPa")
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("load-line displacement (mm)")
    for row in axes:
        row[0].set_ylabel("P (kN)")
    axes[0][0].plot([], [], color=MODES["joint"], label="joint failure")
    axes[0][0].plot([], [], color=MODES["brick"], label="brick failure")
    axes[0][0].legend()
    _save(fig, path)


def predicted_vs_simulated(fits, path):
    """Predicted against simulated strength, and the prediction error, per
    failure mode."""
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    lo, hi = np.inf, -np.inf
    for mode, (eq, y) in fits.items():
        ax.scatter(y, eq["fitted"], s=10, color=MODES[mode], label=f"{mode} (MAPE {eq['mape']:.1f} %)")
        ax2.hist(100 * (eq["fitted"] - y) / y, bins=30, alpha=0.6, color=MODES[mode], label=mode)
        lo, hi = min(lo, y.min()), max(hi, y.max())
    if np.isfinite(lo):
        ax.plot([lo, hi], [lo, hi], "k--", lw=1)
    ax.set_xlabel("simulated strength (MPa)")
    ax.set_ylabel("predicted strength (MPa)")
    ax.legend()
    ax.grid(alpha=0.3)
    ax2.set_xlabel("prediction error (%)")
    ax2.set_ylabel("runs")
    ax2.legend()
    _save(fig, path)


def design_comparison(levels, pred, band, lg, as_stepped, as_line, simulated, path):
    """Lower-of-two prediction at mean properties with a +-1 SD band against
    sigma_v, beside the Lourenco-Gaetani and AS3700 rules and the simulated
    mean strengths."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(levels, pred, "k-", lw=2, label="prediction (lower of two)")
    ax.fill_between(levels, pred - band, pred + band, color="k", alpha=0.15, label="+- 1 SD")
    ax.plot(levels, np.full_like(levels, lg[0]), "--", color="tab:blue", label="Lourenco-Gaetani stepped")
    ax.plot(levels, np.full_like(levels, lg[1]), "--", color="tab:red", label="Lourenco-Gaetani brick")
    ax.plot(levels, as_stepped, ":", color="tab:blue", lw=2, label="AS3700 stepped")
    ax.plot(levels, as_line, ":", color="tab:red", lw=2, label="AS3700 line")
    if simulated is not None:
        ax.plot(simulated[0], simulated[1], "o", color="tab:green", label="simulated mean (non-spatial)")
    ax.set_xlabel("sigma_v (MPa)")
    ax.set_ylabel("strength (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    _save(fig, path)
