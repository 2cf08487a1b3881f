"""Latin Hypercube samples of a study's random variables (docs/study.md, 6-7).

Each variable has a marginal (lognormal, normal, truncated normal or
uniform, by its study file); named pairs have a target Pearson
correlation, the others none.

Method:
1. scipy.stats.qmc.LatinHypercube gives n stratified points in [0, 1)^d;
   each maps to its marginal by the inverse CDF (exactly one sample per
   stratum of every variable).
2. Iman & Conover (1982), iterated, on the standardised sample values: the
   columns are re-ordered (never changed) so that their Pearson correlation
   matrix approaches the target (the named pairs', 0 elsewhere).  Working
   on the values rather than on normal scores targets the correlation the
   study reports (Pearson of the variables) directly; re-ordering keeps
   every marginal's strata exact.
3. On few samples (a spatial field of 24 units) Iman-Conover settles on an
   ordering whose correlation can be far from the target (0.27 to 0.55
   instead of 0.5 over the study's 100 unit fields): while a correlation
   is more than CORRELATION_TOL from its target, two values of one column
   are swapped at random and the swap kept when it brings the matrix
   closer (``refine_correlation``), again without changing any value.
The achieved correlation matrix is returned with the samples.
"""
import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Variable:
    name: str
    dist: str          # lognormal, normal, truncated_normal or uniform
    mean: float = None
    cov: float = None  # or sd
    sd: float = None
    bounds: tuple = None   # (min, max): the distribution cut to them
    setting: str = None    # the scene setting it drives (a study file's)
    per: str = None        # 'unit' or 'joint': what carries one value per item

    def frozen(self):
        """The marginal as a scipy distribution (ppf, mean, ...)."""
        from scipy import stats         # on first use: reading a study file needs none of it (0.5 s)
        sd = self.sd if self.sd is not None else (self.cov * self.mean if self.mean is not None else None)
        if self.dist == "uniform":
            lo, hi = self.bounds
            return stats.uniform(loc=lo, scale=hi - lo)
        if self.dist in ("normal", "truncated_normal"):
            parent = stats.norm(loc=self.mean, scale=sd)
        else:
            cov = self.cov if self.cov is not None else sd / self.mean
            parent = Lognormal(math.sqrt(math.log(1.0 + cov ** 2)), self.mean / math.sqrt(1.0 + cov ** 2))
        if self.bounds is None:
            return parent
        lo, hi = self.bounds
        if self.dist in ("normal", "truncated_normal"):
            return stats.truncnorm((lo - self.mean) / sd, (hi - self.mean) / sd, loc=self.mean, scale=sd)
        return _Truncated(parent, lo, hi)


class Lognormal:
    """The lognormal distribution with log-SD ``s`` and median ``scale``,
    scipy's lognorm(s, scale=scale) to the last bit on a CPU without
    AVX-512, and on every CPU: its exp and log are the C library's, value
    by value.  numpy's vectorised exp and log run code of their own on
    AVX-512 CPUs, which differs in the last bit or two for some values, and
    the samples, a study's inputs, must not depend on the machine."""

    def __init__(self, s, scale):
        self.s, self.scale = s, scale

    def ppf(self, u):
        from scipy import special
        z = self.s * special.ndtri(np.asarray(u, float))
        return _elementwise(math.exp, z) * self.scale + 0.0        # as scipy: ppf * scale + loc

    def cdf(self, x):
        from scipy import special
        return special.ndtr(_elementwise(math.log, np.asarray(x, float) / self.scale) / self.s)

    def mean(self):
        return math.sqrt(math.exp(self.s * self.s)) * self.scale


def _elementwise(fn, x):
    """fn (a function of the math module) on each value of the array x."""
    return np.vectorize(fn, otypes=[float])(x)


class _Truncated:
    """A distribution cut to [lo, hi]: ppf(u) = F^-1(F(lo) + u (F(hi) - F(lo)))."""

    def __init__(self, parent, lo, hi):
        self.parent, self.a, self.b = parent, parent.cdf(lo), parent.cdf(hi)

    def ppf(self, u):
        return self.parent.ppf(self.a + np.asarray(u) * (self.b - self.a))

    def mean(self):
        u = (np.arange(10_000) + 0.5) / 10_000
        return float(np.mean(self.ppf(u)))


def iman_conover(values, target, iterations=20):
    """Re-orders the columns of ``values`` (n x d) so that their Pearson
    correlation approaches ``target`` (d x d): Iman & Conover (1982), with
    the standardised values themselves as the reference and the step
    repeated (each pass corrects the correlation left by the last).  Each
    column keeps its values, so Latin Hypercube strata are untouched."""
    P = np.linalg.cholesky(target)
    z = (values - values.mean(axis=0)) / values.std(axis=0)
    for _ in range(iterations):
        Q = np.linalg.cholesky(np.corrcoef(z, rowvar=False))
        T = z @ np.linalg.inv(Q).T @ P.T
        order = [np.argsort(np.argsort(T[:, j])) for j in range(z.shape[1])]
        z = np.column_stack([np.sort(z[:, j])[order[j]] for j in range(z.shape[1])])
    return np.column_stack([np.sort(values[:, j])[order[j]] for j in range(z.shape[1])])


CORRELATION_TOL = 0.02     # every pair within this of its target correlation


def refine_correlation(x, target, rng, tol=CORRELATION_TOL, tries=200_000):
    """Swaps of two values within a column of ``x`` (n x d), each kept when
    it lowers the sum of squared differences between the Pearson matrix
    and ``target``, until every pair is within ``tol`` of its target, or
    after ``tries`` swaps, or once no swap is left that would lower it: 20
    times as many swaps in a row kept none as there are distinct swaps,
    d n (n - 1) / 2 (each tried about 20 times: a better one is missed with
    a chance of e^-20).  A small sample cannot reach ``tol``: 8 samples of
    the study's four variables ran all 200,000 swaps (45 s), now 2,240
    after the last kept one.  The committed studies reach ``tol`` with at
    most 29 swaps kept none in a row.  Returns the re-ordered copy."""
    x = x.copy()
    n, d = x.shape
    stall = 20 * d * n * (n - 1) // 2

    def miss(c):
        return float(np.sum((c - target) ** 2)), float(np.abs(c - target).max())

    err, worst = miss(np.corrcoef(x, rowvar=False))
    since = 0
    for _ in range(tries):
        if worst <= tol or since >= stall:
            break
        j = int(rng.integers(d))
        a, b = rng.choice(n, 2, replace=False)
        x[[a, b], j] = x[[b, a], j]
        e, w = miss(np.corrcoef(x, rowvar=False))
        if e < err:
            err, worst, since = e, w, 0
        else:
            x[[a, b], j] = x[[b, a], j]
            since += 1
    return x


def _target(names, correlations):
    """The correlation matrix of ``names`` with the given pairs' values."""
    target = np.eye(len(names))
    for (a, b), rho in correlations.items():
        i, j = names.index(a), names.index(b)
        target[i, j] = target[j, i] = rho
    return target


def lhs(n, variables, correlations, seed):
    """n Latin Hypercube samples of ``variables`` with the given Pearson
    correlations between named pairs ((name, name) -> rho).  Returns (dict
    name -> array, achieved Pearson correlation matrix)."""
    from scipy.stats import qmc
    rng = np.random.default_rng(seed)
    d = len(variables)
    u = qmc.LatinHypercube(d=d, seed=rng).random(n)
    x = np.column_stack([v.frozen().ppf(u[:, k]) for k, v in enumerate(variables)])
    names = [v.name for v in variables]
    target = _target(names, correlations)
    if n > d > 1:
        x = iman_conover(x, target)
        x = refine_correlation(x, target, rng)
    achieved = np.atleast_2d(np.corrcoef(x, rowvar=False))
    return {nm: x[:, k] for k, nm in enumerate(names)}, achieved


def wallette_samples(n, seed, variables, correlations):
    """(the samples of a variant that draws one value per wallette: a
    DataFrame of sample and each variable's value, SI; their achieved
    Pearson correlation matrix), reproducible from ``seed``."""
    import pandas as pd
    values, achieved = lhs(n, variables, correlations, seed=np.random.SeedSequence(seed).spawn(1)[0])
    return pd.DataFrame({"sample": np.arange(n), **values}), achieved


def study_samples(n, seed, n_units, n_joints, variables, correlations):
    """The study's samples (docs/study.md, 6-8), reproducible from ``seed``.

    Returns (wallettes, items, achieved), the draws of a variant that draws
    per 'wallette' and of one that draws per 'items':
    * wallettes: DataFrame, one row per sample: sample and one value of
      each variable for the whole wallette (SI: Pa, degrees);
    * items: DataFrame, one row per sample with list columns: the
      variables carried per unit (``per``), n_units values from one LHS of
      size n_units with their correlations, and those per joint from one
      LHS of size n_joints;
    * achieved: correlation matrix of the wallettes' sample.
    The spatial draws use seeds spawned from ``seed`` (numpy SeedSequence),
    one per simulation, so each is reproducible on its own."""
    wallettes, achieved = wallette_samples(n, seed, variables, correlations)
    return wallettes, item_samples(n, seed, n_units, n_joints, variables, correlations), achieved


def item_samples(n, seed, n_units, n_joints, variables, correlations):
    """The draws of a variant that draws per 'items' (study_samples)."""
    import pandas as pd
    groups = [(tuple(v for v in variables if v.per == per), count) for per, count in (("unit", n_units),
                                                                                       ("joint", n_joints))]
    rows = []
    for i, ss in enumerate(np.random.SeedSequence([seed, 1]).spawn(n)):
        row = {"sample": i}
        for (group, count), s in zip(groups, ss.spawn(2)):
            names = {v.name for v in group}
            within = {pair: rho for pair, rho in correlations.items() if set(pair) <= names}
            drawn, _ = lhs(count, group, correlations=within, seed=s) if group else ({}, None)
            row.update({k: x.tolist() for k, x in drawn.items()})
        rows.append(row)
    return pd.DataFrame(rows)


def field_samples(n, seed, variables, correlations, centres, length):
    """Random fields of the variables carried per unit and per joint, one
    draw per sample (a study variant that draws 'field').

    Each variable is a Gaussian field mapped to its marginal (u = Phi(g),
    x = F^-1(u)).  Between two items at distance r on the wall's face the
    Gaussian correlation is exp(-r / ``length``) (the exponential, Markov,
    kernel; positive definite in any dimension); variables of the same
    items are correlated as ``correlations`` says, at the same point, in
    Gaussian space (a separable model: covariance = kernel x cross
    correlation; for a lognormal pair the Pearson correlation of the values
    is then slightly below rho, 0.49 for rho 0.5 at COV 0.25 and 0.30).
    ``centres`` gives each item's (x, z) (masonry.Geometry.item_centres).
    A long ``length`` gives one value for the wallette, a short one
    independent items.  Returns a DataFrame like the spatial table of
    ``study_samples``: sample and a list per variable.  Seeds are spawned
    from ``seed`` per sample, so each draw is reproducible on its own."""
    import pandas as pd
    rows = []
    for i, ss in enumerate(np.random.SeedSequence([seed, 2]).spawn(n)):
        row = {"sample": i}
        for per, s in zip(("unit", "joint"), ss.spawn(2)):
            group = [v for v in variables if v.per == per]
            if group:
                row.update(_field(group, correlations, centres[per], length, np.random.default_rng(s)))
        rows.append(row)
    return pd.DataFrame(rows)


def _field(group, correlations, xy, length, rng):
    from scipy import stats
    r = np.linalg.norm(xy[:, None, :] - xy[None, :, :], axis=-1)
    kernel = np.linalg.cholesky(np.exp(-r / length) + 1e-10 * np.eye(len(xy)))
    names = [v.name for v in group]
    cross = np.linalg.cholesky(_target(names, {p: c for p, c in correlations.items() if set(p) <= set(names)}))
    g = kernel @ rng.standard_normal((len(xy), len(group))) @ cross.T
    u = stats.norm.cdf(g)
    return {v.name: np.asarray(v.frozen().ppf(u[:, k]), float).tolist() for k, v in enumerate(group)}


def records(table):
    """A table of study_samples as a list of plain dicts (JSON): one per
    sample, arrays as lists."""
    return [{k: (v.tolist() if hasattr(v, "tolist") else v) for k, v in r.items()} for r in table.to_dict("records")]


def sampling_check(wallettes, achieved, variables):
    """The sample drawn per wallette against its targets: per variable its
    distribution, target and sample mean and COV, and its row of the
    achieved correlation matrix (columns corr_<name>)."""
    import pandas as pd
    names = [v.name for v in variables]
    rows = []
    for k, v in enumerate(variables):
        x = wallettes[v.name]
        rows.append(dict(variable=v.name, distribution=v.dist, mean_target=v.mean, mean_sample=x.mean(),
                         cov_target=v.cov, cov_sample=x.std(ddof=1) / x.mean(),
                         **{f"corr_{n}": achieved[k, j] for j, n in enumerate(names)}))
    return pd.DataFrame(rows)
