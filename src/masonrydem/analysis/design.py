"""The wallette's characteristic flexural strength per level, with an
interval that carries the lab tests' uncertainty as well as the number of
simulations, beside the design rules (docs/lab-to-design.md, sections 8 to 10).

The lab's uncertainty reaches the wallette without new simulations: the
study drew each lab-fitted input x_j from its study file's distribution
q_j (the fit's mean and cov); draws theta*_b of the fits' parameters from
their pivotal quantities (lab_draws) weight the study's runs by
w_i = prod_j p_j(x_ij; theta*_b) / q_j(x_ij), so that they stand for a
study drawn at theta*_b (importance sampling; Kish's effective sample
size (sum w)^2 / sum w^2 says how many runs they are worth).  The runs'
own uncertainty enters each draw through pivotal quantities too
(linear_replicates, gap_replicates), never through a bootstrap of the
runs, whose percentiles fall short at a few runs.  Assumptions: a
lab-fitted input is drawn one value per wallette and independently of the
others (a correlation with another input is kept as the study drew it).
"""
import math

import numpy as np
import pandas as pd
from scipy import stats

from ..errors import InputError
from . import fractiles

# EN 1996-1-1's recommended f_xk1 and f_xk2 (the plane of failure parallel
# and perpendicular to the bed joints, N/mm2) for clay units, by mortar:
# read from a secondary transcription of the standard's tables (NOTE 2 to
# 3.6.3(3)), not from the standard itself; check against EN 1996-1-1 and
# its National Annex, which may set others
FXK1_CLAY = {"general purpose, f_m < 5 N/mm2": 0.10, "general purpose, f_m >= 5 N/mm2": 0.10,
             "thin layer": 0.15, "lightweight": 0.10}
FXK2_CLAY = {"general purpose, f_m < 5 N/mm2": 0.20, "general purpose, f_m >= 5 N/mm2": 0.40,
             "thin layer": 0.15, "lightweight": 0.10}


def density(distribution, mean, cov):
    """The study's lognormal or normal of ``mean`` and ``cov`` (arrays
    broadcast) as a scipy distribution, with logpdf."""
    if distribution == "lognormal":
        s = np.sqrt(np.log1p(np.square(cov)))
        return stats.lognorm(s, scale=mean / np.sqrt(1 + np.square(cov)))
    if distribution == "normal":
        return stats.norm(mean, cov * mean)
    raise InputError("distribution", f"{distribution!r}: a lab fit is lognormal or normal")


def moments(x):
    """(mean, cov with n - 1) along the last axis: the fit's estimator."""
    m = np.mean(x, -1)
    return m, np.std(x, -1, ddof=1) / m


def lab_draws(values, distribution, draws, rng):
    """(mean*, cov*), each of length ``draws``: the fit's parameters drawn
    from their generalized pivotal quantities (Weerahandi; Krishnamoorthy
    and Mathew, Statistical Tolerance Regions, 2009), on the log scale for
    a lognormal fit: sigma* = s sqrt((n - 1) / U), U chi-square with n - 1
    degrees of freedom, mu* = mu - Z sigma* / sqrt(n), Z standard normal,
    (mu, s) the fit's.  Their quantiles give the exact intervals of mu, of
    sigma and of mu + z sigma (a fractile); a parametric bootstrap's fall
    short at a lab's n (at n = 10 the true 5 % fractile lay below the
    bootstrap's 95 % interval for 9 % of constructed labs, not 2.5 %)."""
    m, c = moments(np.asarray(values, float))
    n, g = len(values), np.random.default_rng(rng)
    mu, s = regressor_moments(distribution, m, c)
    s = np.sqrt(s)
    s_d = s * np.sqrt((n - 1) / g.chisquare(n - 1, draws))
    mu_d = mu - g.standard_normal(draws) * s_d / math.sqrt(n)
    if distribution == "lognormal":
        return np.exp(mu_d + np.square(s_d) / 2), np.sqrt(np.expm1(np.square(s_d)))
    return mu_d, s_d / mu_d


def regressor(distribution, x):
    """A lab-fitted input on the scale where its fit is normal: ln x or x."""
    return np.log(x) if distribution == "lognormal" else np.asarray(x, float)


def regressor_moments(distribution, mean, cov):
    """(mean, variance) of regressor(x) for x of the fit (``mean``, ``cov``)."""
    if distribution == "lognormal":
        s2 = np.log1p(np.square(cov))
        return np.log(mean) - s2 / 2, s2
    if distribution == "normal":
        return mean, np.square(mean * cov)
    raise InputError("distribution", f"{distribution!r}: a lab fit is lognormal or normal")


def ess(w):
    """Kish's effective sample size along the last axis."""
    return np.sum(w, -1) ** 2 / np.sum(np.square(w), -1)


def weighted_quantile(y, w, p):
    """The smallest y whose cumulative weight reaches p of the total (the
    inverse of the weighted empirical distribution; along the last axis)."""
    order = np.argsort(y, -1)
    ys, cw = np.take_along_axis(y, order, -1), np.cumsum(np.take_along_axis(np.broadcast_to(w, y.shape), order, -1), -1)
    i = np.argmax(cw >= p * cw[..., -1:] * (1 - 1e-12), -1)
    return np.take_along_axis(ys, i[..., None], -1)[..., 0]


def weighted_fractile(y, w, p, basis):
    """The p fractile of the weighted runs: ``lognormal`` exp(m + z_p s)
    with the weighted mean and variance of ln y (reliability weights: the
    sample variance with n - 1 at equal weights), else the weighted
    empirical quantile."""
    if basis != "lognormal":
        return weighted_quantile(y, w, p)
    ly, w = np.log(y), np.broadcast_to(w, y.shape)
    sw = w.sum(-1)
    m = (w * ly).sum(-1) / sw
    var = (w * np.square(ly - m[..., None])).sum(-1) / (sw - np.square(w).sum(-1) / sw)
    return np.exp(m + stats.norm.ppf(p) * np.sqrt(var))


def linear_replicates(ly, U, w, EU, VU, p, rng):
    """The p fractile of ln y at each row's lab draw, (lab alone, lab and
    runs), from the runs weighted by the row's ``w`` (B, n).  The weighted
    mean m and variance s^2 of ln y (reliability weights) are corrected by
    the regressors U (n, k), whose mean EU and variance VU (B, k) at the
    draw are known (control variates): with b the weighted least-squares
    slopes, m + b.(EU - weighted mean of U) and s^2 + b'(diag VU - weighted
    covariance of U) b, so that what the inputs explain no longer rests on
    the few runs in the weighted tails.  The runs' uncertainty: the normal
    sample's pivotal quantities with the ESS as the number of runs,
    m* = m - Z s* / sqrt(ESS), s* = s sqrt((ESS - 1) / U'), U' chi-square
    with ESS - 1 degrees of freedom; at equal weights and no correction
    their percentiles are the runs-only exact interval's ends.  NaN where
    the ESS is not above k + 1 (no runs to spare for the slopes)."""
    g = np.random.default_rng(rng)
    sw, ne = w.sum(-1), ess(w)
    denom = sw - np.square(w).sum(-1) / sw

    def centred(v):
        return v - np.einsum("bn,n...->b...", w, v)[:, None] / sw[:, None, *([None] * (v.ndim - 1))]
    dy, dU = centred(ly), centred(U)
    SU = np.einsum("bn,bni,bnj->bij", w, dU, dU) / denom[:, None, None]
    spare = ne > U.shape[1] + 1
    b = np.linalg.solve(np.where(spare[:, None, None], SU, np.eye(U.shape[1])),
                        np.einsum("bn,bni,bn->bi", w, dU, dy)[..., None] / denom[:, None, None])[..., 0]
    m = np.einsum("bn,n->b", w, ly) / sw + (b * (EU - np.einsum("bn,ni->bi", w, U) / sw[:, None])).sum(-1)
    s2 = (np.einsum("bn,bn->b", w, np.square(dy)) / denom + (b * b * VU).sum(-1)
          - np.einsum("bi,bij,bj->b", b, SU, b))
    n = np.where(spare, ne, 2.0)
    s_d = np.sqrt(s2 * (n - 1) / g.chisquare(n - 1))
    m_d = m - g.standard_normal(m.shape) * s_d / np.sqrt(n)
    z = stats.norm.ppf(p)
    return (np.where(spare, m + z * np.sqrt(s2), np.nan), np.where(spare, m_d + z * s_d, np.nan))


def gap_replicates(y, w, p, rng):
    """Distribution-free: the p fractile bracketed at each row's weights
    (B, n) by the fiducial of the order statistics (Hannig, Iyer and
    Patterson 2006): exponential masses on the n + 1 gaps around the sorted
    runs, the gap above run k weighted by that run's w and the gap below
    the smallest by the smallest run's (a draw that widens the distribution
    weights its tails' runs, and with them the gaps beyond them); the runs
    either side of where the cumulative mass crosses p (-inf below the
    smallest, inf above the largest).  At equal weights its percentiles
    are the order-statistic interval's ends."""
    g = np.random.default_rng(rng)
    order = np.argsort(y)
    ys, ws = np.asarray(y, float)[order], w[:, order]
    mass = g.exponential(size=(w.shape[0], ys.size + 1)) * np.concatenate([ws[:, :1], ws], -1)
    c = np.cumsum(mass[:, :-1], -1) / mass.sum(-1, keepdims=True)
    k = (c <= p).sum(-1)
    ext = np.concatenate([[-np.inf], ys, [np.inf]])
    return ext[k], ext[k + 1]


def weighted_runs(inputs, sampling, lab):
    """The runs' weights at the fits (N,) and at each lab draw (B, N), each
    scaled to a largest of 1, and the regressors: U (N, k) and their mean
    and variance at each draw, EU and VU (B, k).  ``inputs``: lab-fitted
    input -> its N values; ``sampling``: input -> the distribution the
    study drew it from; ``lab``: input -> (distribution, lab values,
    (mean*, cov*)) shared across levels (lab_draws)."""
    lw_hat, lw, U, EU, VU = 0.0, 0.0, [], [], []
    for var, (dist, values, (m_b, c_b)) in lab.items():
        x = np.asarray(inputs[var], float)
        q = sampling[var].logpdf(x)
        lw_hat = lw_hat + density(dist, *moments(np.asarray(values, float))).logpdf(x) - q
        lw = lw + density(dist, m_b[:, None], c_b[:, None]).logpdf(x[None, :]) - q
        U.append(regressor(dist, x))
        e, v = regressor_moments(dist, m_b, c_b)
        EU.append(e)
        VU.append(v)
    return (np.exp(lw_hat - lw_hat.max()), np.exp(lw - lw.max(-1, keepdims=True)), np.stack(U, 1), np.stack(EU, 1),
            np.stack(VU, 1))


def propagate(y, inputs, sampling, lab, rng, basis="lognormal", p=fractiles.FRACTILE,
              conf=fractiles.CONFIDENCE):
    """The p fractile of the strengths ``y`` (N runs) under the lab fits,
    and its intervals (the arguments as weighted_runs takes them).  Each
    lab draw weights the runs: ``lognormal`` by linear_replicates, else by
    the weighted quantile (lab alone) and gap_replicates (lab and runs).
    Returns the point (at the fits, every run), the interval, the lab-only
    interval (NaN ends where more than the tail's share of draws have no
    bound) and the ESS at the fits and over the draws (median, 5 %
    quantile)."""
    y = np.asarray(y, float)
    w_hat, w, U, EU, VU = weighted_runs(inputs, sampling, lab)
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        if basis == "lognormal":
            lab_only, both = np.exp(linear_replicates(np.log(y), U, w, EU, VU, p, rng))
            lower, upper = both, both
        else:
            lab_only = weighted_quantile(np.broadcast_to(y, w.shape), w, p)
            lower, upper = gap_replicates(y, w, p, rng)
    a = 100 * (1 - conf) / 2
    e = ess(w)
    return {"point": float(weighted_fractile(y, w_hat, p, basis)),
            "interval": (_end(lower, a, 0.0), _end(upper, 100 - a, np.inf)),
            "lab_only": (_end(lab_only, a, 0.0), _end(lab_only, 100 - a, np.inf)), "ess_point": float(ess(w_hat)),
            "ess_median": float(np.median(e)), "ess_05": float(np.quantile(e, 0.05))}


def _end(replicates, q, unbounded):
    """The q percentile of the replicates (a draw without a bound, NaN or
    infinite, counts as ``unbounded``: 0 for a lower end, inf for an upper
    one); NaN where that is where the percentile falls."""
    r = np.where(np.isfinite(replicates), replicates, unbounded)
    v = float(np.percentile(r, q, method="inverted_cdf"))
    return v if 0 < v < np.inf else np.nan


def design_table(runs, level_column, inputs, sampling, lab, gamma_m, fxk2, as3700_inputs, rng, draws=1000,
                 direction="horizontal", fxk1=None):
    """Per level of the ok runs: the wallette's characteristic flexural
    strength (MPa) with its interval (lab and runs), the lab-only and the
    runs-only intervals, the ESS, the design value f_xk / gamma_m, EN
    1996-1-1's f_xk2 (``fxk2``, MPa) and its design value, and AS 3700's
    capacities at the lab's characteristic values (``as3700_inputs``:
    (f'_mt, f'_ut) in MPa, or None where it does not apply).  ``inputs``:
    lab-fitted input -> its runs table column (SI = column x ``scale``).
    In vertical bending (``direction``) EN 1996-1-1's apparent f_xk1 +
    sigma_d (``fxk1``, 6.3.1) and AS 3700's vertical rule instead."""
    from .validation import as3700, as3700_vertical
    if not gamma_m > 0:
        raise InputError("design.gamma_M", f"{gamma_m}: a partial factor is above 0")
    ok = runs[runs.ok]
    boots = {v: (dist, vals, lab_draws(vals, dist, draws, g))
             for (v, (dist, vals)), g in zip(lab.items(), np.random.default_rng(rng).spawn(len(lab)))}
    rows = []
    for k, (level, group) in enumerate(ok.groupby(level_column)):
        y = group.strength_mpa.to_numpy(float)
        p_sw = fractiles.lognormal_fit(y)
        basis = "lognormal" if p_sw >= fractiles.NORMALITY_P else "non-parametric"
        x = {v: group[col].to_numpy(float) * scale for v, (col, scale) in inputs.items()}
        r = propagate(y, x, sampling, boots, np.random.default_rng([rng, k]), basis)
        runs_only = (fractiles.lognormal_fractile if basis == "lognormal" else fractiles.empirical_fractile)(y)
        row = {level_column: level, "runs": y.size, "basis": basis, "f_xk_mpa": r["point"],
               "f_xk_lo_mpa": r["interval"][0], "f_xk_hi_mpa": r["interval"][1],
               "lab_only_lo_mpa": r["lab_only"][0], "lab_only_hi_mpa": r["lab_only"][1],
               "runs_only_lo_mpa": runs_only[1], "runs_only_hi_mpa": runs_only[2],
               "ess": r["ess_point"], "ess_median": r["ess_median"], "ess_05": r["ess_05"],
               "gamma_M": gamma_m, "f_xd_mpa": r["point"] / gamma_m}
        if direction == "vertical":
            row.update(f_xk1_app_mpa=fxk1 + level, f_xd1_app_mpa=fxk1 / gamma_m + level)
            if as3700_inputs is not None:
                row.update(as3700_vertical_mpa=float(as3700_vertical(as3700_inputs[0], np.array([level]))[0]))
        else:
            row.update(f_xk2_mpa=fxk2, f_xd2_mpa=fxk2 / gamma_m)
            if as3700_inputs is not None:
                stepped, line = as3700(*as3700_inputs, np.array([level]))
                row.update(as3700_stepped_mpa=float(stepped[0]), as3700_line_mpa=float(line[0]))
        rows.append(row)
    return pd.DataFrame(rows)


def _span(row, key):
    return fractiles.span(row[f"{key}_lo_mpa"], row[f"{key}_hi_mpa"])


def caption_lines(table, level_column, level_unit):
    """One line per level for the report page and the command's output."""
    out = []
    for r in table.to_dict("records"):
        if "f_xk1_app_mpa" in r:
            rules = (f"; EN 1996-1-1 f_xk1 + sigma_d {r['f_xk1_app_mpa']:.2f} MPa (design "
                     f"{r['f_xd1_app_mpa']:.3f})")
            if "as3700_vertical_mpa" in r and not math.isnan(r["as3700_vertical_mpa"]):
                rules += f"; AS 3700 vertical {r['as3700_vertical_mpa']:.3f} MPa"
        else:
            rules = f"; EN 1996-1-1 f_xk2 {r['f_xk2_mpa']:.2f} MPa (design {r['f_xd2_mpa']:.3f})"
            if "as3700_stepped_mpa" in r and not math.isnan(r["as3700_stepped_mpa"]):
                rules += f"; AS 3700 stepped {r['as3700_stepped_mpa']:.3f}, line {r['as3700_line_mpa']:.3f} MPa"
        out.append(f"{r[level_column]:g} {level_unit}: f_xk {r['f_xk_mpa']:.3f} MPa ({_span(r, 'f_xk')}; "
                   f"lab only {_span(r, 'lab_only')}, runs only {_span(r, 'runs_only')}; {r['basis']}, "
                   f"{r['runs']} runs, ESS {r['ess']:.1f}, median over the draws {r['ess_median']:.1f}), "
                   f"design f_xk / {r['gamma_M']:g} = {r['f_xd_mpa']:.3f} MPa" + rules)
    return out


def en_words(direction, mortar):
    """The design caption's words on EN 1996-1-1 in the study's direction."""
    if direction == "vertical":
        return (f"EN 1996-1-1's recommended f_xk1 for clay units, {mortar} (from a secondary transcription of the\n"
                "standard's table), with the precompression added as its 6.3.1 adds it (f_xk1 + sigma_d)")
    return (f"EN 1996-1-1's recommended f_xk2 for clay units, {mortar} (from a secondary transcription of the\n"
            "standard's table), gives no credit for the precompression")


def as3700_words(as3700, bond=None, units=None, direction="horizontal"):
    """The design caption's words on AS 3700 (``as3700``: study_inputs'
    characteristic values, or None): its rules given at the lab's values,
    or why none are given (they need both the bond and the units' modulus
    of rupture from lab sheets: the config's design.bond and design.units)."""
    if as3700 is not None and direction == "vertical":
        return "AS 3700's vertical-bending rule (capacity factor 1) at the lab's characteristic flexural bond adds it too"
    if as3700 is not None:
        return ("AS 3700's horizontal-bending rules (capacity factor 1) at the lab's characteristic flexural bond "
                "and unit modulus of rupture do")
    missing = " and ".join(f"design.{k} ({v or 'not set'})" for k, v in (("bond", bond), ("units", units)))
    return ("AS 3700's horizontal-bending rules, which do, need both the lab's flexural bond and its units' modulus "
            f"of rupture, each a variable fitted to a lab sheet ({missing}): none are given here")


def lab_words(study):
    """Each lab-fitted variable's lab value beside the model's: 'bond, 10
    results of the lab's flexural bond strength, mean 0.3453 MPa x 0.6667
    (EN 1992-1-1:2004) = the model's mean 0.2302 MPa'."""
    from ..scene import shown
    from .predict import cite
    out = []
    for name, r in study.provenance.items():
        unit, size, _ = shown(study.units[name])
        out.append(f"{name}, {r['n']} results of the lab's {r['lab']['quantity']}, mean {r['lab']['mean']} x "
                   f"{r['conversion']['factor']:.4g} ({cite(r['conversion']['source'])}) = the model's mean "
                   f"{study.variable(name).mean / size:.4g} {unit}")
    return "; ".join(out)


def study_inputs(study, bond=None, units=None):
    """What the re-weighting needs of a typed study whose variables carry
    lab records (study.file: provenance): input -> (distribution, the lab's
    results as the model's parameter in SI); input -> the distribution the
    study drew it from; input -> (runs table column, SI per shown unit);
    and AS 3700's (f'_mt, f'_ut) in MPa, the characteristic values of the
    tests of the variables ``bond`` (bond wrench) and ``units`` (units'
    flexure), or None unless both are given with lab records."""
    from ..scene import shown, to_si
    from .labsheet import read_sheet
    if not study.provenance:
        raise InputError("study.variables", "no variable has a lab record (provenance): fit one (masonrydem fit)")
    lab, sampling, columns = {}, {}, {}
    for name, record in study.provenance.items():
        v, unit = study.variable(name), study.units[name]
        if v.dist not in ("lognormal", "normal") or v.cov is None:
            raise InputError(f"study.variables.{name}", "a lab-fitted variable is lognormal or normal, with a cov")
        values = read_sheet(record["data"], unit)["values"] * record["conversion"]["factor"]
        lab[name] = (v.dist, values)
        sampling[name] = density(v.dist, v.mean, v.cov)
        columns[name] = (study.column(name), shown(unit)[1])
    for name in (bond, units):
        if name is not None and name not in study.units:
            raise InputError("design", f"{name!r} is not a variable of the study ({', '.join(study.units)})")
    as3700 = None
    if bond in study.provenance and units in study.provenance:
        as3700 = tuple(to_si(study.provenance[n]["lab"]["characteristic"]["en1990"], "Pa", n) / 1e6
                       for n in (bond, units))
    return lab, sampling, columns, as3700
