"""Sobol sensitivity indices of the study's strength, per variant, level and
failure mode, from a Gaussian process fitted to the study's own runs; the
intervals hold what the runs leave open about the strength, the process's
misfit included.

Method:
1. **Inputs.** Sobol indices need independent inputs.  The inputs are
   written as functions of independent standard normal scores w through a
   Gaussian copula: z = L w, with L the Cholesky factor of the correlation
   matrix in the study file's order, each input its marginal's quantile of
   Phi(z) (input_map; its ``scores`` the inverse, the runs' scores).  So an
   input earlier in the file (f_tu) carries, in its index, the part of a
   later correlated input (E_b) that it determines (its *full* index in the
   sense of Mara and Tarantola, 2012), and the later one's index is its
   *independent* part.  The target correlation is taken for the normal
   scores; for the study's lognormal pair that gives a Pearson correlation
   of the values of 0.49 for 0.5.
2. **Gaussian process.** A Gaussian process regression of the strength on
   the runs' scores (scikit-learn): a Matern 5/2 kernel with a length scale
   per input, plus white noise, its parameters by maximum likelihood on at
   most FIT_RUNS of the runs (a seeded subset: the likelihood's cost grows
   with the cube of the runs, and its few parameters are settled long
   before), then conditioned on all of them.  Its leave-one-out R^2 (cv_r2)
   and the share of the strength's variance it gives to noise
   (noise_share) are reported; the indices are shares of the rest.  Below
   MIN_R2 the inputs do not explain the strength (a variant that draws per
   unit or joint, whose strength follows the field of unit and joint
   values, not the recorded field means), and no index is given.
3. **Indices.** First-order S1 and total ST of the process's posterior mean
   over the study's input distribution, by SALib's Sobol sequence in the
   scores (Saltelli's scheme, N_BASE base points) and its estimators
   (Saltelli 2010 for S1, Jansen for ST).
4. **Intervals.** DRAWS functions drawn from the posterior (a prior draw by
   FEATURES random Fourier features, conditioned on the runs: Matheron's
   rule) and the indices of each on the same points.  The draws differ
   where the runs leave the strength open, between runs and across a kink
   such as the switch from joint to brick failure, so their spread holds
   the surrogate's misfit, which a bootstrap of a fitted polynomial does
   not.  A draw is rougher than the posterior mean, and rougher than a
   smooth strength may be: its indices lie to one side of the mean's (a
   total index above, from interactions the roughness adds), and the
   mean's may lie as far to the other side of the truth.  So the interval
   joins the draws' 2.5 and 97.5 % points with their reflection about the
   mean's index (the percentile and the basic interval together), within
   0 to 1.  On the lower of two linear strengths over the study's inputs
   from 100 runs and on the Ishigami function from 200 runs, it held the
   indices in 36 to 40 of 40 seeds per input (docs/study.md, 12a).
5. **Inputs without an effect.** Per input, a likelihood-ratio test of the
   process without the input against the process with it (a length scale
   at its bound: the 50:50 mixture of chi2 with 0 and 1 degrees of freedom,
   at 1 - CONFIDENCE).  Where it cannot tell the input's effect from none,
   its intervals start at 0 (the test inverted): every posterior draw gives
   an input a total index above 0, also one without any effect.  The test
   is on the runs the parameters were fitted to.

The indices of one failure mode are those of that mode's strength law, the
process fitted to its runs and evaluated over the whole input range,
including where the other mode governs.
"""
import numpy as np
import pandas as pd
from scipy import stats

from ..study.copula import CLIP, CopulaMap
from .needs import MIN_RUNS
from .plots import save_figure

N_BASE = 2 ** 12
DRAWS = 200
FEATURES = 1000
CONFIDENCE = 0.95
MIN_R2 = 0.5
FIT_RUNS = 200


def input_map(variables, correlations, scale):
    """The inputs as a function of independent uniforms (module docstring,
    1): ``to_inputs(u)`` for u (n x d) in [0, 1), columns in the order of
    ``variables`` (sampling.Variable), each multiplied by scale[name] (the
    factor to the runs table's unit); ``to_inputs.scores(x)`` the
    independent standard normal scores of the inputs x (its inverse, after
    Phi^-1)."""
    return CopulaMap(variables, correlations, scale)


def _kernel(amplitude, length_scales, noise):
    """Matern 5/2 with a length scale per input, plus white noise (module
    docstring, 2), from the given parameters (the bounds fixed)."""
    from sklearn.gaussian_process.kernels import ConstantKernel, Matern, WhiteKernel
    return (ConstantKernel(amplitude, (1e-3, 1e3)) * Matern(length_scales, (1e-2, 1e3), nu=2.5)
            + WhiteKernel(noise, (1e-8, 1.0)))


def fit_process(w, y, seed=0, kernel=None, restarts=2, optimize=True):
    """The Gaussian process of y on the scores w (scikit-learn, fitted;
    ``kernel`` the starting one, or the one kept where not ``optimize``).
    A length scale or the noise at its bound (an input without effect, runs
    without noise) is an answer, not a failure: scikit-learn's warning of
    it is kept quiet."""
    import warnings
    from sklearn.exceptions import ConvergenceWarning
    from sklearn.gaussian_process import GaussianProcessRegressor
    gp = GaussianProcessRegressor(kernel or _kernel(1.0, np.ones(w.shape[1]), 1e-2), normalize_y=True,
                                  n_restarts_optimizer=restarts, random_state=seed,
                                  optimizer="fmin_l_bfgs_b" if optimize else None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return gp.fit(w, y)


def fit_subset(runs, fit_runs=FIT_RUNS, seed=0):
    """The runs the process's parameters are fitted to (module docstring,
    2): all (a slice) up to ``fit_runs``, else ``fit_runs`` of them drawn
    without replacement from ``seed``, in their order."""
    if runs <= fit_runs:
        return slice(None)
    return np.sort(np.random.default_rng(seed).choice(runs, fit_runs, replace=False))


def condition(gp, w, y):
    """The process with gp's fitted parameters conditioned on the runs (w,
    y), its parameters not refitted: the amplitude and noise, which hold in
    units of the strength's variance over gp's runs, rescaled to that over
    these."""
    k, scale = gp.kernel_, (gp._y_train_std / np.std(y)) ** 2
    kernel = _kernel(k.k1.k1.constant_value * scale, k.k1.k2.length_scale, k.k2.noise_level * scale)
    return fit_process(w, y, kernel=kernel, optimize=False)


def fit_quality(gp, y):
    """(leave-one-out R^2, noise share of the variance) of a fitted process,
    the LOO residuals in closed form: alpha_i / (K^-1)_ii."""
    k_inv = np.linalg.inv(gp.kernel_(gp.X_train_))
    loo = (k_inv @ gp.y_train_) / np.diag(k_inv) * gp._y_train_std
    noise = gp.kernel_.k2.noise_level * gp._y_train_std ** 2
    return 1.0 - float(np.mean(loo ** 2) / np.var(y)), float(noise / np.var(y))


def posterior_draws(gp, w_at, draws=DRAWS, seed=0, features=FEATURES, chunk=4096):
    """The process's posterior mean and ``draws`` functions from its
    posterior at the scores w_at (rows): len(w_at) x (1 + draws), column 0
    the mean; the latent strength, without the noise.  A draw is a prior
    draw by random Fourier features (the Matern kernel's spectral density:
    a Student t with 2 nu degrees of freedom over the length scales)
    conditioned on the runs by Matheron's rule; the mean is the same rule
    with the prior draw and the noise 0.

    The features' cosines and their sum over the features, most of the
    indices' time, are in single precision (the phases in double): on the
    study's groups a draw moves by at most 6e-5 of the draws' standard
    deviation, the mean not at all (its prior part is zero), and the
    study's interval ends by at most one in their fourth digit."""
    k = gp.kernel_
    amp, ls, nu, noise = k.k1.k1.constant_value, k.k1.k2.length_scale, k.k1.k2.nu, k.k2.noise_level
    rng = np.random.default_rng(seed)
    freq = (rng.standard_normal((features, w_at.shape[1])) / ls
            * np.sqrt(2 * nu / rng.chisquare(2 * nu, (features, 1))))
    phase = rng.uniform(0, 2 * np.pi, features)
    theta = np.column_stack([np.zeros(features), rng.standard_normal((features, draws))]).astype(np.float32)

    def prior(z):
        cosines = np.cos((z @ freq.T + phase).astype(np.float32))
        return np.sqrt(2 * amp / features) * (cosines @ theta).astype(float)

    x = gp.X_train_
    eps = np.sqrt(noise) * np.column_stack([np.zeros(len(x)), rng.standard_normal((len(x), draws))])
    chol = np.linalg.cholesky(k(x))                       # the kernel with its noise
    v = np.linalg.solve(chol.T, np.linalg.solve(chol, gp.y_train_[:, None] - prior(x) - eps))
    out = np.empty((len(w_at), 1 + draws))
    for s in range(0, len(w_at), chunk):
        z = w_at[s:s + chunk]
        out[s:s + chunk] = prior(z) + k.k1(z, x) @ v
    return out * gp._y_train_std + gp._y_train_mean


def no_effect(gp, w, y):
    """Per input, True where the likelihood-ratio test (module docstring,
    5) cannot tell its effect from none: the process refitted without it,
    from the fitted parameters."""
    crit = stats.chi2.ppf(1 - 2 * (1 - CONFIDENCE), 1)
    k, out = gp.kernel_, []
    if w.shape[1] == 1:
        return np.array([False])
    for j in range(w.shape[1]):
        kernel = _kernel(k.k1.k1.constant_value, np.delete(k.k1.k2.length_scale, j), k.k2.noise_level)
        red = fit_process(np.delete(w, j, axis=1), y, kernel=kernel, restarts=0)
        out.append(2 * (gp.log_marginal_likelihood_value_ - red.log_marginal_likelihood_value_) < crit)
    return np.array(out)


def sobol_points(d, n=N_BASE, seed=0):
    """SALib's Sobol sequence for S1 and ST of d independent uniforms."""
    from SALib.sample import sobol
    problem = dict(num_vars=d, names=[f"w{k}" for k in range(d)], bounds=[[0.0, 1.0]] * d)
    return sobol.sample(problem, n, calc_second_order=False, seed=seed)


def indices(y, d, n=N_BASE):
    """(S1, ST), arrays of d (d x k for k columns of outputs), from the
    outputs y at sobol_points(d, n) (SALib's order: per base point A, the
    d mixed points, B), each column centred first, as SALib's analysis
    does: the first-order estimator mean(f_B (f_ABi - f_A)) is not
    invariant to a shift of the output."""
    from SALib.analyze.sobol import first_order, total_order
    y = np.asarray(y, float).reshape(n * (d + 2), -1)
    y = (y - y.mean(axis=0)).reshape(n, d + 2, -1)
    a, b = y[:, 0], y[:, -1]
    s1 = np.array([first_order(a, y[:, 1 + j], b) for j in range(d)])
    st = np.array([total_order(a, y[:, 1 + j], b) for j in range(d)])
    return (s1[:, 0], st[:, 0]) if y.shape[2] == 1 else (s1, st)


def interval(estimate, draws, no_effect=False):
    """The interval of an index: the 2.5 and 97.5 % points of its draws
    (the last axis), joined with their reflection about the posterior
    mean's index ``estimate``, within 0 to 1 (where every index lies);
    from 0 where ``no_effect`` (module docstring, 4 and 5)."""
    tail = 50 * (1 - CONFIDENCE)
    lo, hi = np.percentile(draws, [tail, 100 - tail], axis=-1)
    lo, hi = np.minimum(lo, 2 * estimate - hi), np.maximum(hi, 2 * estimate - lo)
    return np.where(no_effect, 0.0, np.clip(lo, 0.0, 1.0)), np.clip(hi, 0.0, 1.0)


def group_indices(x, y, points, to_inputs, n=N_BASE, draws=DRAWS, seed=0, fit_runs=FIT_RUNS):
    """The indices of one group's runs (x: n_runs x d inputs, y: strength):
    dict of surrogate, cv_r2, noise_share and, where the process explains
    the strength, S1, ST (arrays), their intervals S1_lo ... ST_hi and
    no_effect (module docstring), the parameters fitted to at most
    ``fit_runs`` runs.  On one thread of linear algebra (a process per job,
    as a rule's threads say: two threads beside another busy process took
    six times as long)."""
    from threadpoolctl import threadpool_limits
    with threadpool_limits(1):
        return _group_indices(x, y, points, to_inputs, n, draws, seed, fit_runs)


def _group_indices(x, y, points, to_inputs, n, draws, seed, fit_runs):
    """group_indices' work."""
    w, sub = to_inputs.scores(x), fit_subset(len(y), fit_runs, seed)
    fitted = fit_process(w[sub], y[sub], seed)
    gp = fitted if isinstance(sub, slice) else condition(fitted, w, y)
    r2, noise = fit_quality(gp, y)
    out = dict(surrogate="gaussian process", cv_r2=r2, noise_share=noise)
    if r2 < MIN_R2:
        return out
    d, at = x.shape[1], stats.norm.ppf(np.clip(points, CLIP, 1 - CLIP))
    s1, st = indices(posterior_draws(gp, at, draws, seed), d, n)        # column 0: the mean
    out["S1"], out["ST"] = s1[:, 0], st[:, 0]
    null = no_effect(fitted, w[sub], y[sub])
    lo, hi = interval(np.array([s1[:, 0], st[:, 0]]), np.array([s1[:, 1:], st[:, 1:]]), null)
    out.update(S1_lo=lo[0], S1_hi=hi[0], ST_lo=lo[1], ST_hi=hi[1], no_effect=null)
    return out


def sensitivity_table(runs, level, columns, to_inputs, n=N_BASE, draws=DRAWS, seed=0, jobs=1):
    """One row per variant, level, failure mode ('all' for all runs) and
    input: runs, surrogate, cv_r2, noise_share, S1, ST, their intervals and
    no_effect (empty where the group has fewer than MIN_RUNS runs or the
    process's R^2 is below MIN_R2).  ``columns``: the inputs' columns in the
    runs table, in the order of ``to_inputs``' output (input_map).  The
    groups go on ``jobs`` processes (each group draws from its own seed:
    the same values, to round-off, whichever process fits it; map_blocks)."""
    from .equations import map_blocks
    points, groups = sobol_points(len(columns), n, seed), []
    for (variant, lv), g in runs[runs.ok].groupby(["variant", level.column]):
        for mode in ("all", "joint", "brick"):
            h = g if mode == "all" else g[g.failure_mode == mode]
            groups.append(({"variant": variant, level.column: lv, "mode": mode, "runs": len(h)},
                           h[columns].to_numpy(float), h.strength_mpa.to_numpy(float)))
    fitted = [(x, y) for _, x, y in groups if len(y) >= MIN_RUNS]
    results = iter(map_blocks(_group_block, [[k] for k in range(len(fitted))], jobs, fitted, points, to_inputs, n,
                              draws, seed))
    rows, stat = [], ("S1", "S1_lo", "S1_hi", "ST", "ST_lo", "ST_hi", "no_effect")
    for base, x, y in groups:
        if len(y) < MIN_RUNS:
            rows.append(base)
            continue
        res = next(results)
        for k, col in enumerate(columns):
            rows.append({**base, "input": col, **{s: res[s] for s in ("surrogate", "cv_r2", "noise_share")},
                         **{s: res[s][k] for s in stat if s in res}})
    return pd.DataFrame(rows, columns=["variant", level.column, "mode", "runs", "input", "surrogate", "cv_r2",
                                       "noise_share", *stat])


def _group_block(block, fitted, points, to_inputs, n, draws, seed):
    """group_indices of the one group in ``block`` (map_blocks' unit)."""
    x, y = fitted[block[0]]
    return group_indices(x, y, points, to_inputs, n, draws, seed)


def with_pearson(table, corr, level):
    """The table with the Pearson correlation of each input (statistics'
    correlations.csv, wide: one column per input) and its square, which
    equals S1 for a linear response to independent inputs."""
    keys = ["variant", level.column, "mode"]
    cols = [c for c in table["input"].dropna().unique() if c in corr]
    long = corr.melt(id_vars=keys, value_vars=cols, var_name="input", value_name="pearson")
    out = table.merge(long, on=[*keys, "input"], how="left")
    return out.assign(pearson_sq=out.pearson ** 2)


def no_indices(table):
    """Why a sensitivity table has no index at all, in words (None where it
    has some)."""
    if "ST" in table and table.ST.notna().any():
        return None
    runs = table.loc[table["mode"] == "all", "runs"]
    most = int(runs.max()) if len(runs) else 0
    if most < MIN_RUNS:
        return (f"No Sobol indices: at most {most} runs per variant and level, fewer than the {MIN_RUNS} a "
                f"surrogate needs (give the study samples: {MIN_RUNS} or more)")
    return "No Sobol indices: the inputs the runs record do not explain their strength"


def figure(table, path, level):
    """S1 and ST with their intervals against the level, one panel per
    mode, stacked, beside the squared Pearson correlations (dashed), the
    variant with indices; the inputs told apart by colour and the three
    measures by line, in a legend below the panels."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    has = table.dropna(subset=["ST"])
    modes = [m for m in ("all", "joint", "brick") if m in set(has["mode"])]
    n = max(len(modes), 1)
    fig, axes = plt.subplots(n, 1, figsize=(7, 2.9 * n + 1.1), sharex=True, squeeze=False)
    inputs = list(dict.fromkeys(has["input"]))
    for ax, mode in zip(axes[:, 0], modes):
        g = has[has["mode"] == mode]
        for name, h in g.groupby("input", sort=False):
            color = f"C{inputs.index(name)}"
            x = h[level.column]
            # an interval of the draws need not hold the posterior mean's index: bars from the estimate, clipped
            bars = np.clip([h.ST - h.ST_lo, h.ST_hi - h.ST], 0, None)
            ax.errorbar(x, h.ST, yerr=bars, fmt="o-", color=color, capsize=3)
            ax.plot(x, h.S1, "s:", color=color, ms=4)
            ax.plot(x, h.pearson_sq, "--", color=color, lw=0.8, alpha=0.7)
        ax.set_title(f"{', '.join(sorted(g.variant.unique()))} variant, {mode} failure modes"
                     if mode == "all" else f"{', '.join(sorted(g.variant.unique()))} variant, {mode} failures",
                     fontsize=10)
        ax.set_ylabel("index, r²")
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3)
        ax.tick_params(labelbottom=True)
    axes[-1, 0].set_xlabel(f"{_symbol(level.name)} ({level.unit})" if level.unit else _symbol(level.name))
    # the legend below the panels, never over the data: the inputs by colour, the measures by line
    handles = [Line2D([], [], color=f"C{k}", lw=6) for k in range(len(inputs))] + \
        [Line2D([], [], color="0.3", marker="o", ls="-"), Line2D([], [], color="0.3", marker="s", ls=":", ms=4),
         Line2D([], [], color="0.3", ls="--", lw=0.8)]
    labels = [_symbol(x) for x in inputs] + ["total index $S_T$", "first-order index $S_1$", "squared Pearson $r^2$"]
    fig.tight_layout(rect=(0, 0.7 / fig.get_figheight(), 1, 1))
    fig.legend(handles, labels, fontsize=10, loc="lower center", ncol=min(len(labels), 4), frameon=False)
    save_figure(fig, path)


def _symbol(name):
    """An input's column as a symbol: f_tj_mpa as $f_{tj}$, phi_j_deg as $\\phi_{j}$."""
    head, sub = (name.split("_") + [""])[:2]
    head = f"\\{head}" if head in ("phi", "sigma") else head
    return f"${head}_{{{sub}}}$" if sub else name


def caption_values(table, level, variables, correlations):
    """The sensitivity caption's numbers: per variant and level, the
    process's out-of-sample R^2 and noise share and, where there are
    indices, the inputs by total index (all modes together), an input
    whose effect the test cannot tell from none marked; the correlated
    pairs, the first in ``variables``' order first."""
    order = [v.name for v in variables]
    pairs = "; ".join(f"{' and '.join(sorted(p, key=order.index))}, rho {rho:g}" for p, rho in correlations.items())
    lines = []
    for (variant, lv), g in table[table["mode"] == "all"].groupby(["variant", level.column]):
        if g.runs.iloc[0] < MIN_RUNS:
            lines.append(f"{variant}, {level.text(lv)}: {g.runs.iloc[0]} runs, too few for a surrogate")
            continue
        head = (f"{variant}, {level.text(lv)}: leave-one-out R^2 {g.cv_r2.iloc[0]:.2f}, "
                f"noise {100 * g.noise_share.iloc[0]:.1f} % of the variance")
        if g.ST.isna().all():
            lines.append(f"{head}; no indices: the inputs the runs record (for a variant that draws per unit or "
                         f"joint, the means of its fields) do not explain the strength")
            continue
        ranked = g.sort_values("ST", ascending=False)
        lines.append(head + "; " + ", ".join(
            f"{r.input} **ST {r.ST:.2f}** ({r.ST_lo:.2f} to {r.ST_hi:.2f}{_none(r.no_effect)}), S1 {r.S1:.2f}, "
            f"r^2 {r.pearson_sq:.2f}" for r in ranked.itertuples()))
    return dict(lines="\n".join(f"- {x}" for x in lines), n_base=N_BASE, draws=DRAWS, min_r2=MIN_R2,
                confidence=round(100 * CONFIDENCE), pairs=pairs or "none in this study")


def _none(no_effect):
    """The caption's mark of an input whose effect the test cannot tell from none."""
    return "; effect not told from none" if str(no_effect) == "True" else ""     # numpy's, Python's or read back
