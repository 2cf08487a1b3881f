"""A lab's results fitted: distributions with goodness of fit and a choice
among them, the parameters' intervals, the characteristic value by EN 1990
Annex D beside a 95 %/95 % tolerance bound, and the study file's variable
block with its provenance (docs/lab-to-design.md, sections 4 to 7).

Everything random is drawn from a seed the caller gives (the command's
--seed), so a fit is repeatable to the last digit.
"""
import math

import numpy as np
from scipy import optimize, stats

from ..errors import InputError
from ..scene import shown

FAMILIES = ("normal", "lognormal", "weibull")
STUDY_FAMILIES = ("lognormal", "normal")          # those a study file draws from a mean and a cov
AIC_DELTA = 2.0      # within 2 AICc units: the data do not tell the families apart (Burnham & Anderson)
_SCIPY = {"normal": (stats.norm, None), "lognormal": (stats.lognorm, {"loc": 0.0}),
          "weibull": (stats.weibull_min, {"loc": 0.0})}

# EN 1990:2002 Annex D, Table D1: k_n of the 5 % characteristic value, by n
TABLE_D1 = {"n": (1, 2, 3, 4, 5, 6, 8, 10, 20, 30, math.inf),
            "known": (2.31, 2.01, 1.89, 1.83, 1.80, 1.77, 1.74, 1.72, 1.68, 1.67, 1.64),
            "unknown": (None, None, 3.37, 2.63, 2.33, 2.18, 2.00, 1.92, 1.76, 1.73, 1.64)}


def _checked(values, positive=True):
    x = np.asarray(values, float).ravel()
    if x.size < 3 or not np.all(np.isfinite(x)) or (positive and np.any(x <= 0)) or np.ptp(x) == 0:
        raise InputError("values", "at least 3 finite values, above 0, not all equal")
    return x


def fit_distributions(values, rng, families=FAMILIES, resamples=999):
    """Each family fitted by maximum likelihood (lognormal and Weibull with
    location 0): its parameters, log-likelihood, AICc = 2k - 2 ln L +
    2k(k+1)/(n-k-1) (k = 2; AIC where n <= 3), and the Anderson-Darling
    p-value of scipy.stats.goodness_of_fit, a parametric bootstrap that
    refits each simulated sample, so that the p-value holds with the
    parameters estimated.  ``rng``: a seed; each family draws from its own
    stream of it, so that its p-value does not depend on the others."""
    x = _checked(values)
    n, k = x.size, 2
    streams = dict(zip(FAMILIES, np.random.default_rng(rng).spawn(len(FAMILIES))))
    out = {}
    for fam in families:
        dist, known = _SCIPY[fam]
        fitted = dist(*dist.fit(x, **({"floc": 0.0} if known else {})))
        ll = float(np.sum(fitted.logpdf(x)))
        aic = 2 * k - 2 * ll + (2 * k * (k + 1) / (n - k - 1) if n > k + 1 else 0.0)
        gof = _goodness_of_fit(fam, x, resamples, streams[fam])
        out[fam] = {"loglik": ll, "aicc": aic, "ad_statistic": float(gof.statistic), "ad_pvalue": float(gof.pvalue),
                    "mean": float(fitted.mean()), "cov": float(fitted.std() / fitted.mean())}
    return out


def _goodness_of_fit(family, x, resamples, rng):
    """scipy.stats.goodness_of_fit's Anderson-Darling test of ``family``
    with its parameters estimated.  A Weibull with location 0 is tested as
    the minimum-Gumbel of the logs, its exact image (log of a Weibull of
    shape k and scale s: a Gumbel of the minimum, location log s, scale
    1 / k; maximum likelihood and the statistic, a function of the fitted
    CDF at the values, carry over): the same statistic and p-value,
    ten times as fast (scipy fits the Gumbel in closed form up to one root,
    the Weibull by a general optimiser; tests/test_labfit.py)."""
    if family == "weibull":
        return stats.goodness_of_fit(stats.gumbel_l, np.log(x), statistic="ad", n_mc_samples=resamples, rng=rng)
    dist, known = _SCIPY[family]
    return stats.goodness_of_fit(dist, x, known_params=known, statistic="ad", n_mc_samples=resamples, rng=rng)


def choose(fits, among=FAMILIES):
    """The family of smallest AICc, and those within AIC_DELTA of it, which
    n results cannot tell apart from it (all three have two parameters:
    the ranking is the log-likelihood's)."""
    order = sorted(among, key=lambda f: fits[f]["aicc"])
    close = [f for f in order[1:] if fits[f]["aicc"] - fits[order[0]]["aicc"] < AIC_DELTA]
    note = (f"{order[0]} has the smallest AICc; " + (f"{', '.join(close)} within {AIC_DELTA:g}: n too small to tell "
                                                     "them apart" if close else f"the others {AIC_DELTA:g} or more above"))
    return {"best": order[0], "ranking": order, "indistinguishable": close, "note": note}


def mean_interval(x, conf=0.95):
    """The t interval of the mean, xbar -+ t_{n-1} s / sqrt(n)."""
    x = _checked(x, positive=False)
    h = stats.t.ppf(0.5 + conf / 2, x.size - 1) * x.std(ddof=1) / math.sqrt(x.size)
    return float(x.mean() - h), float(x.mean() + h)


def cov_interval(x, conf=0.95, method="noncentral_t"):
    """The interval of the coefficient of variation of normal data:
    ``noncentral_t`` (exact): sqrt(n) xbar / s is non-central t with n - 1
    degrees of freedom and non-centrality sqrt(n) / COV, inverted;
    ``chi2`` (approximate): the chi-square interval of sigma over the
    sample mean, taken as exact."""
    x = _checked(x)
    n, m, s = x.size, x.mean(), x.std(ddof=1)
    if method == "chi2":
        q = stats.chi2.ppf([0.5 + conf / 2, 0.5 - conf / 2], n - 1)
        return tuple(float(s * math.sqrt((n - 1) / v) / m) for v in q)
    t = math.sqrt(n) * m / s

    def nc(q):
        f = lambda lam: stats.nct.cdf(t, n - 1, lam) - q   # noqa: E731
        return 0.0 if f(0.0) < 0 else optimize.brentq(f, 0.0, 4 * t + 20, xtol=1e-12)
    big, small = nc(0.5 - conf / 2), nc(0.5 + conf / 2)     # the cdf falls as the non-centrality grows
    return float(math.sqrt(n) / big), float(math.sqrt(n) / small) if small > 0 else math.inf


def kn(n, vx_known=False):
    """EN 1990 D7.2's k_n of the 5 % fractile: u_0.95 sqrt(1 + 1/n) with V_X
    known, t_{n-1,0.95} sqrt(1 + 1/n) unknown; 1.645 at n = infinity."""
    z = stats.norm.ppf(0.95)
    if n == math.inf:
        return float(z)
    return float((z if vx_known else stats.t.ppf(0.95, n - 1)) * math.sqrt(1 + 1 / n))


def table_d1(n, vx_known=False):
    """k_n as EN 1990's Table D1 prints it (its n only)."""
    return TABLE_D1["known" if vx_known else "unknown"][TABLE_D1["n"].index(n)]


def _logs(x, distribution):
    if distribution not in STUDY_FAMILIES:
        raise InputError("--distribution", f"{distribution!r}: {' or '.join(STUDY_FAMILIES)}")
    x = _checked(x)
    return (np.log(x), np.exp) if distribution == "lognormal" else (x, lambda v: v)


def characteristic(x, distribution, prior_cov=None):
    """EN 1990 D7.2's 5 % characteristic value: normal m (1 - k_n V),
    lognormal exp(m_y - k_n s_y); with a documented prior COV (V_X known)
    V = prior_cov and s_y = sqrt(ln(1 + V^2))."""
    y, back = _logs(x, distribution)
    known = prior_cov is not None
    k = kn(y.size, known)
    if distribution == "normal":
        return float(y.mean() * (1 - k * (prior_cov if known else y.std(ddof=1) / y.mean()))), k
    sy = math.sqrt(math.log(1 + prior_cov ** 2)) if known else y.std(ddof=1)
    return float(back(y.mean() - k * sy)), k


def tolerance_factor(n, content=0.95, conf=0.95):
    """ISO 16269-6's one-sided factor, sigma unknown: t'_conf(n - 1,
    z_content sqrt(n)) / sqrt(n), t' the non-central t's quantile."""
    return float(stats.nct.ppf(conf, n - 1, stats.norm.ppf(content) * math.sqrt(n)) / math.sqrt(n))


def tolerance_bound(x, distribution, content=0.95, conf=0.95):
    """The lower bound below which at most 1 - content of the population
    lies, with confidence conf: xbar - k s (on the logs for a lognormal)."""
    y, back = _logs(x, distribution)
    return float(back(y.mean() - tolerance_factor(y.size, content, conf) * y.std(ddof=1)))


def fractile_interval(x, distribution, p=0.05, conf=0.95):
    """The confidence interval of the p fractile: with x_p = mu + z_p sigma,
    sqrt(n) (xbar - x_p) / s is non-central t (n - 1, -z_p sqrt(n)); exact
    for normal data, and on the logs for lognormal data.  ``x`` a row a lab
    gives arrays of ends."""
    v = np.asarray(x, float)
    _logs(v.ravel(), distribution)
    y = np.log(v) if distribution == "lognormal" else v
    n = y.shape[-1]
    t = stats.nct.ppf([0.5 + conf / 2, 0.5 - conf / 2], n - 1, -stats.norm.ppf(p) * math.sqrt(n))
    m, s = y.mean(-1), y.std(-1, ddof=1)
    back = np.exp if distribution == "lognormal" else (lambda a: a)
    return back(m - t[0] * s / math.sqrt(n)), back(m - t[1] * s / math.sqrt(n))


def measured(lab, unit, seed, distribution=None, prior_cov=None, resamples=999):
    """What a read sheet (labsheet.read_sheet) measured, fitted: (the lab's
    numbers, the fits, the distribution the characteristic values and a
    study file's block use).  The numbers are in the unit a study shows
    ``unit`` (SI) in: mean and cov with their intervals, the fits' AICc and
    p-values, the choice and why, and the characteristic values.  The
    distribution is ``distribution`` where given, else the AICc's best of
    those a study file draws from (STUDY_FAMILIES), which need not be the
    best of all (``choice`` says so)."""
    text, size, _ = shown(unit)
    x = lab["values"] / size                      # fitted in the unit a study shows (MPa)
    fits = fit_distributions(x, seed, resamples=resamples)
    dist = distribution or choose(fits, STUDY_FAMILIES)["best"]
    q = lambda v: f"{float(v):.4g} {text}".rstrip()   # noqa: E731
    xk, k = characteristic(x, dist, prior_cov)
    lo, hi = fractile_interval(x, dist)
    cov = float(x.std(ddof=1) / x.mean())
    lab_numbers = {
        "quantity": lab["quantity"], "method": lab["method"], "mean": q(x.mean()),
        "mean_95": [q(v) for v in mean_interval(x)], "cov": round(cov, 4), "cov_95": [round(v, 4) for v in cov_interval(x)],
        "fit": {"seed": seed, "resamples": resamples, "choice": _choice(fits, dist, distribution is not None),
                **{f: {"aicc": round(r["aicc"], 3), "ad_pvalue": round(r["ad_pvalue"], 3)} for f, r in fits.items()}},
        "characteristic": {"en1990": q(xk), "k_n": round(k, 3), "v_x": "known" if prior_cov else "unknown",
                           **({"prior_cov": prior_cov} if prior_cov else {}),
                           "fractile_5_95": [q(lo), q(hi)], "tolerance_95_95": q(tolerance_bound(x, dist))}}
    return lab_numbers, fits, dist


def _choice(fits, dist, given):
    """The choice of ``dist`` in words: the AICc's ranking of all families,
    and why ``dist`` is the one used (given, or the better of those a study
    file draws from)."""
    why = ("as --distribution gives it" if given else
           f"the smaller AICc of {' and '.join(STUDY_FAMILIES)}, the families a study file draws from")
    return f"{choose(fits)['note']}; used: {dist}, {why}"


def block(lab, name, setting, unit, factor, source, seed, per=None, distribution=None, prior_cov=None,
          resamples=999):
    """The study file's variable ``name`` from a read sheet (labsheet.read_sheet)
    and the conversion to the model's parameter (``factor`` and its
    ``source``): the study's numbers (mean and cov of the model's
    parameter, the distribution ``measured`` chose) and under
    ``provenance`` the data, the conversion and what the test measured
    (``measured``)."""
    lab_numbers, fits, dist = measured(lab, unit, seed, distribution, prior_cov, resamples)
    text, size, _ = shown(unit)
    x = lab["values"] / size
    provenance = {"data": lab["path"], "sha256": lab["sha256"], "n": int(x.size), "screened": lab["screened"],
                  "conversion": {"factor": round(float(factor), 6), "source": source}, "lab": lab_numbers}
    entry = {"setting": setting, **({"per": per} if per else {}), "distribution": dist,
             "mean": f"{float(factor * x.mean()):.4g} {text}".rstrip(), "cov": lab_numbers["cov"],
             "provenance": provenance}
    return {name: entry}, fits


def summary(lab, lab_numbers, fits, dist, conversion=None):
    """The lines ``masonrydem fit`` prints: the sheet, the screened rows,
    the fits, the choice, the statistics and characteristic values of what
    it measured (``measured``), and where a block follows, its conversion
    (``conversion``: (name, factor, source))."""
    p = lab_numbers
    lines = [f"{lab['name']}: {lab['quantity']}, {lab['values'].size} results ({lab['method']})"]
    lines += [f"screened: row {s['row']} ({s['failure']}): {s['reason']}" for s in lab["screened"]]
    lines += [f"{f}: AICc {r['aicc']:.2f}, Anderson-Darling p {r['ad_pvalue']:.3f} (bootstrap, "
              f"{p['fit']['resamples']} resamples)" for f, r in fits.items()]
    c = p["characteristic"]
    lines += [p["fit"]["choice"], f"mean {p['mean']} ({p['mean_95'][0]} to {p['mean_95'][1]}), cov {p['cov']} "
              f"({p['cov_95'][0]} to {p['cov_95'][1]}); 95 % intervals",
              f"characteristic (EN 1990 D7.2, {dist}, k_n {c['k_n']}, V_X {c['v_x']}): "
              f"{c['en1990']}; 95/95 tolerance bound (ISO 16269-6) {c['tolerance_95_95']}; 5 % fractile "
              f"{c['fractile_5_95'][0]} to {c['fractile_5_95'][1]} (95 %)"]
    if conversion:
        name, factor, source = conversion
        lines.append(f"{name} = {round(float(factor), 6):g} x {lab['quantity']}: {source}")
    return lines
