"""A study's random inputs as functions of independent uniforms, and a
pick-freeze design of them: what the study's Sobol indices
(analysis/sensitivity.py) and their check on the solver
(analysis/sobol_check.py) share.  Apart from sampling.py, whose Latin
Hypercube samples this does not touch: a change here draws no sample
again."""
import numpy as np
from scipy import stats

CLIP = 1e-12           # uniforms kept off 0 and 1: finite normal scores


def correlation_matrix(names, correlations):
    """The target correlation matrix of ``names`` ((a, b) -> rho; 0 elsewhere)."""
    r = np.eye(len(names))
    for (a, b), rho in correlations.items():
        i, j = names.index(a), names.index(b)
        r[i, j] = r[j, i] = rho
    return r


class CopulaMap:
    """The inputs ``variables`` (sampling.Variable) as a function of
    independent uniforms u (n x d, columns in their order) through a
    Gaussian copula: normal scores z = L w, w = Phi^-1(u), L the Cholesky
    factor of the target correlation matrix in that order, each input its
    marginal's quantile of Phi(z), times scale[name] (the factor to a runs
    table's unit; 1 where not given).  So an input earlier in the order
    carries the part of a later correlated input that it determines.
    ``scores(x)`` is the inverse after Phi^-1: the independent standard
    normal scores w of inputs x (in the scaled units).  The target
    correlation is taken for the normal scores, not the values (0.5 for
    the study's lognormal pair gives a Pearson correlation of the values
    of 0.49).  A class: it goes to other processes."""

    def __init__(self, variables, correlations, scale=None):
        self.names = [v.name for v in variables]
        self.chol = np.linalg.cholesky(correlation_matrix(self.names, correlations))
        self.marginals = [v.frozen() for v in variables]
        self.scale = [1.0 if scale is None else scale[n] for n in self.names]

    def __call__(self, u):
        z = stats.norm.ppf(np.clip(u, CLIP, 1 - CLIP)) @ self.chol.T
        return np.column_stack([s * m.ppf(stats.norm.cdf(z[:, k]))
                                for k, (s, m) in enumerate(zip(self.scale, self.marginals))])

    def scores(self, x):
        """The scores w (n x d) of the inputs x (n x d, the scaled units)."""
        u = np.column_stack([m.cdf(np.asarray(x, float)[:, k] / self.scale[k]) for k, m in enumerate(self.marginals)])
        return np.linalg.solve(self.chol, stats.norm.ppf(np.clip(u, CLIP, 1 - CLIP)).T).T


def pick_freeze(variables, correlations, base, seed):
    """Saltelli's pick-freeze design of ``variables``: (u, x).  SALib's
    scrambled Sobol sequence in 2d dimensions (sobol.sample without
    second-order terms) gives ``base`` rows of the matrices A and B; per
    row, A, then A with its column i taken from B for each input i, then B:
    base (d + 2) points u in the independent uniforms, x the inputs there
    in SI (CopulaMap)."""
    from SALib.sample import sobol
    d = len(variables)
    problem = dict(num_vars=d, names=[v.name for v in variables], bounds=[[0.0, 1.0]] * d)
    u = sobol.sample(problem, base, calc_second_order=False, seed=seed)
    return u, CopulaMap(variables, correlations)(u)
