"""Sobol sensitivity indices of the study's strength, per variant, level and
failure mode, on a surrogate fitted to the study's own runs.

Method:
1. **Surrogate.** A linear and a quadratic (ridge) regression of the
   strength on the random inputs, each scored by 5-fold cross-validated
   R^2 on the group's runs; the better one is kept and its out-of-sample
   R^2 reported.  Below MIN_R2 the inputs do not explain the strength (a
   variant that draws per unit or joint, whose strength follows the field
   of unit and joint values, not the wallette's recorded field means; or
   too few runs for the surrogate), and no index is given.
2. **Indices.** First-order S1 and total ST Sobol indices of the surrogate
   over the study's input distribution, by SALib's Sobol sequence
   (Saltelli's scheme, N_BASE base points) and its estimators (Saltelli
   2010 for S1, Jansen for ST).
3. **Correlated inputs.** Sobol indices need independent inputs.  The
   inputs are written as functions of independent uniforms through a
   Gaussian copula: normal scores z = L w, with L the Cholesky factor of
   the correlation matrix in the study file's order, each input its
   marginal's quantile of Phi(z).  So an input earlier in the file (f_tu)
   carries, in its index, the part of a later correlated input (E_b) that
   it determines (its *full* index in the sense of Mara and Tarantola,
   2012), and the later one's index is its *independent* part.  The
   target correlation is taken for the normal scores; for the study's
   lognormal pair that gives a Pearson correlation of the values of 0.49
   for 0.5.
4. **Intervals.** The group's runs resampled BOOTSTRAP times, the
   surrogate refitted to each resample and the indices computed again on
   the same Sobol points; the 2.5 and 97.5 % percentiles.  They hold the
   uncertainty of the fit to the runs; the Sobol points' own error is
   below 0.01 at N_BASE (tests/test_sensitivity.py).

The indices of one failure mode are those of that mode's strength law, the
surrogate fitted to its runs and evaluated over the whole input range,
including where the other mode governs.
"""
import numpy as np
import pandas as pd
from scipy import stats

N_BASE = 2 ** 12
BOOTSTRAP = 200
MIN_R2 = 0.5
MIN_RUNS = 10


def input_map(variables, correlations, scale):
    """The inputs as a function of independent uniforms (module docstring,
    3): ``to_inputs(u)`` for u (n x d) in [0, 1), columns in the order of
    ``variables`` (sampling.Variable), each multiplied by scale[name] (the
    factor to the runs table's unit)."""
    names = [v.name for v in variables]
    r = np.eye(len(names))
    for (a, b), rho in correlations.items():
        i, j = names.index(a), names.index(b)
        r[i, j] = r[j, i] = rho
    chol = np.linalg.cholesky(r)
    marginals = [v.frozen() for v in variables]

    def to_inputs(u):
        z = stats.norm.ppf(np.clip(u, 1e-12, 1 - 1e-12)) @ chol.T
        return np.column_stack([scale[n] * m.ppf(stats.norm.cdf(z[:, k]))
                                for k, (n, m) in enumerate(zip(names, marginals))])
    return to_inputs


def surrogates():
    """The candidate surrogates, unfitted (scikit-learn pipelines)."""
    from sklearn.linear_model import LinearRegression, RidgeCV
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import PolynomialFeatures, StandardScaler
    return {"linear": make_pipeline(StandardScaler(), LinearRegression()),
            "quadratic": make_pipeline(StandardScaler(), PolynomialFeatures(2, include_bias=False), StandardScaler(),
                                       RidgeCV(alphas=np.logspace(-3, 3, 13)))}


def choose_surrogate(x, y, seed=0):
    """(name, cross-validated R^2) of the better surrogate for x -> y."""
    from sklearn.model_selection import KFold, cross_val_score
    folds = KFold(5, shuffle=True, random_state=seed)
    scores = {k: float(cross_val_score(m, x, y, cv=folds, scoring="r2").mean()) for k, m in surrogates().items()}
    best = max(scores, key=scores.get)
    return best, scores[best]


def sobol_points(d, n=N_BASE, seed=0):
    """SALib's Sobol sequence for S1 and ST of d independent uniforms."""
    from SALib.sample import sobol
    problem = dict(num_vars=d, names=[f"w{k}" for k in range(d)], bounds=[[0.0, 1.0]] * d)
    return sobol.sample(problem, n, calc_second_order=False, seed=seed)


def indices(y, d, n=N_BASE):
    """(S1, ST), arrays of d, from the outputs y at sobol_points(d, n)."""
    from SALib.analyze.sobol import first_order, separate_output_values, total_order
    a, b, ab, _ = separate_output_values(np.asarray(y, float), d, n, False)
    return (np.array([first_order(a, ab[:, j], b) for j in range(d)]),
            np.array([total_order(a, ab[:, j], b) for j in range(d)]))


def group_indices(x, y, points, to_inputs, n=N_BASE, bootstrap=BOOTSTRAP, seed=0):
    """The indices of one group's runs (x: n_runs x d inputs, y: strength):
    dict of surrogate, cv_r2 and, where the surrogate explains the
    strength, S1, ST (arrays) and their intervals S1_lo ... ST_hi."""
    from sklearn.base import clone
    name, r2 = choose_surrogate(x, y, seed)
    out = dict(surrogate=name, cv_r2=r2)
    if r2 < MIN_R2:
        return out
    model, at = surrogates()[name], to_inputs(points)
    d = x.shape[1]
    out["S1"], out["ST"] = indices(model.fit(x, y).predict(at), d, n)
    rng = np.random.default_rng(seed)
    draws = []
    for _ in range(bootstrap):
        pick = rng.integers(0, len(y), len(y))
        draws.append(indices(clone(model).fit(x[pick], y[pick]).predict(at), d, n))
    draws = np.asarray(draws)                    # bootstrap x (S1, ST) x d
    lo, hi = np.percentile(draws, [2.5, 97.5], axis=0)
    out.update(S1_lo=lo[0], S1_hi=hi[0], ST_lo=lo[1], ST_hi=hi[1])
    return out


def sensitivity_table(runs, level, columns, to_inputs, n=N_BASE, bootstrap=BOOTSTRAP, seed=0, jobs=1):
    """One row per variant, level, failure mode ('all' for all runs) and
    input: runs, surrogate, cv_r2, S1, ST and their intervals (empty where
    the group has fewer than MIN_RUNS runs or its surrogate's R^2 is below
    MIN_R2).  ``columns``: the inputs' columns in the runs table, in the
    order of ``to_inputs``' output.  The groups go on ``jobs`` processes
    (each group draws from its own seed: the same values, to round-off,
    whichever process fits it; map_blocks)."""
    from .equations import map_blocks
    points, groups = sobol_points(len(columns), n, seed), []
    for (variant, lv), g in runs[runs.ok].groupby(["variant", level.column]):
        for mode in ("all", "joint", "brick"):
            h = g if mode == "all" else g[g.failure_mode == mode]
            groups.append(({"variant": variant, level.column: lv, "mode": mode, "runs": len(h)},
                           h[columns].to_numpy(float), h.strength_mpa.to_numpy(float)))
    fitted = [(x, y) for _, x, y in groups if len(y) >= MIN_RUNS]
    results = iter(map_blocks(_group_block, [[k] for k in range(len(fitted))], jobs, fitted, points, to_inputs, n,
                              bootstrap, seed))
    rows = []
    for base, x, y in groups:
        if len(y) < MIN_RUNS:
            rows.append(base)
            continue
        res = next(results)
        for k, col in enumerate(columns):
            rows.append({**base, "input": col, "surrogate": res["surrogate"], "cv_r2": res["cv_r2"],
                         **{s: res[s][k] for s in ("S1", "S1_lo", "S1_hi", "ST", "ST_lo", "ST_hi") if s in res}})
    return pd.DataFrame(rows, columns=["variant", level.column, "mode", "runs", "input", "surrogate", "cv_r2",
                                       "S1", "S1_lo", "S1_hi", "ST", "ST_lo", "ST_hi"])


def _group_block(block, fitted, points, to_inputs, n, bootstrap, seed):
    """group_indices of the one group in ``block`` (map_blocks' unit)."""
    x, y = fitted[block[0]]
    return group_indices(x, y, points, to_inputs, n, bootstrap, seed)


def with_pearson(table, corr, level):
    """The table with the Pearson correlation of each input (statistics'
    correlations.csv, wide: one column per input) and its square, which
    equals S1 for a linear response to independent inputs."""
    keys = ["variant", level.column, "mode"]
    cols = [c for c in table["input"].dropna().unique() if c in corr]
    long = corr.melt(id_vars=keys, value_vars=cols, var_name="input", value_name="pearson")
    out = table.merge(long, on=[*keys, "input"], how="left")
    return out.assign(pearson_sq=out.pearson ** 2)


def figure(table, path, level):
    """S1 and ST with their intervals against the level, one panel per
    mode, beside the squared Pearson correlations (dashed), the variant
    with indices."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    has = table.dropna(subset=["ST"])
    modes = [m for m in ("all", "joint", "brick") if m in set(has["mode"])]
    fig, axes = plt.subplots(1, max(len(modes), 1), figsize=(5 * max(len(modes), 1), 4), sharey=True, squeeze=False)
    for ax, mode in zip(axes[0], modes):
        g = has[has["mode"] == mode]
        for k, (name, h) in enumerate(g.groupby("input", sort=False)):
            color = f"C{k}"
            x = h[level.column]
            # a percentile interval need not hold its estimate (an index near 0): bars from the estimate, clipped
            bars = np.clip([h.ST - h.ST_lo, h.ST_hi - h.ST], 0, None)
            sym = _symbol(name)
            ax.errorbar(x, h.ST, yerr=bars, fmt="o-", color=color, capsize=3, label=f"{sym}: total index $S_T$")
            ax.plot(x, h.S1, "s:", color=color, ms=4, label=f"{sym}: first-order index $S_1$")
            ax.plot(x, h.pearson_sq, "--", color=color, lw=0.8, alpha=0.7, label=f"{sym}: squared Pearson $r^2$")
        ax.set_title(f"{', '.join(sorted(g.variant.unique()))} variant, {mode} failure modes"
                     if mode == "all" else f"{', '.join(sorted(g.variant.unique()))} variant, {mode} failures")
        ax.set_xlabel(f"{_symbol(level.name)} ({level.unit})" if level.unit else _symbol(level.name))
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("Sobol index, squared Pearson r")
    # the legend beside the panels, never over the data
    fig.legend(*axes[0][0].get_legend_handles_labels(), fontsize=8, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


def _symbol(name):
    """An input's column as a symbol: f_tj_mpa as $f_{tj}$, phi_j_deg as $\\phi_{j}$."""
    head, sub = (name.split("_") + [""])[:2]
    head = f"\\{head}" if head in ("phi", "sigma") else head
    return f"${head}_{{{sub}}}$" if sub else name


def caption_values(table, level, variables, correlations):
    """The sensitivity caption's numbers: per variant and level, the
    surrogate's out-of-sample R^2 and, where there are indices, the inputs
    by total index (all modes together); the correlated pairs, the first
    in ``variables``' order first."""
    order = [v.name for v in variables]
    pairs = "; ".join(f"{' and '.join(sorted(p, key=order.index))}, rho {rho:g}" for p, rho in correlations.items())
    lines = []
    for (variant, lv), g in table[table["mode"] == "all"].groupby(["variant", level.column]):
        if g.runs.iloc[0] < MIN_RUNS:
            lines.append(f"{variant}, {level.text(lv)}: {g.runs.iloc[0]} runs, too few for a surrogate")
            continue
        head = (f"{variant}, {level.text(lv)}: {g.surrogate.iloc[0]} surrogate, "
                f"cross-validated R^2 {g.cv_r2.iloc[0]:.2f}")
        if g.ST.isna().all():
            lines.append(f"{head}; no indices: the inputs the runs record (for a variant that draws per unit or "
                         f"joint, the means of its fields) do not explain the strength")
            continue
        ranked = g.sort_values("ST", ascending=False)
        lines.append(head + "; " + ", ".join(
            f"{r.input} **ST {r.ST:.2f}** ({r.ST_lo:.2f} to {r.ST_hi:.2f}), S1 {r.S1:.2f}, r^2 {r.pearson_sq:.2f}"
            for r in ranked.itertuples()))
    return dict(lines="\n".join(f"- {x}" for x in lines), n_base=N_BASE, bootstrap=BOOTSTRAP, min_r2=MIN_R2,
                pairs=pairs or "none in this study")
