"""The wallette's characteristic flexural strength per level, with an
interval that carries the lab tests' uncertainty as well as the number of
simulations, beside the design rules (docs/lab-to-design.md, sections 8 to 10).

The lab's uncertainty reaches the wallette without new simulations: the
study drew each lab-fitted input x_j from its study file's distribution
q_j (the fit's mean and cov); a parametric bootstrap of the lab (n values
drawn from the fit, their mean and cov taken as the fit takes them) gives
parameters theta*_b, and the study's runs, weighted by
w_i = prod_j p_j(x_ij; theta*_b) / q_j(x_ij), stand for a study drawn at
theta*_b (importance sampling; Kish's effective sample size (sum w)^2 /
sum w^2 says how many runs they are worth).  Assumptions: a lab-fitted
input is drawn one value per wallette and independently of the others
(a correlation with another input is kept as the study drew it).
"""
import math

import numpy as np
import pandas as pd
from scipy import stats

from ..errors import InputError
from . import fractiles

# EN 1996-1-1's recommended f_xk2 (the plane of failure perpendicular to the
# bed joints, N/mm2) for clay units, by mortar: read from a secondary
# transcription of the standard's table (NOTE 2 to 3.6.3(3)), not from the
# standard itself; check against EN 1996-1-1 and its National Annex
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


def lab_resamples(values, distribution, resamples, rng):
    """(mean*, cov*), each of length ``resamples``: n values drawn from the
    fit of the lab's n ``values``, their mean and cov (parametric bootstrap)."""
    m, c = moments(np.asarray(values, float))
    return moments(density(distribution, m, c).rvs(size=(resamples, len(values)), random_state=rng))


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


def propagate(y, inputs, sampling, lab, rng, basis="lognormal", p=fractiles.FRACTILE,
              conf=fractiles.CONFIDENCE, resamples=1000):
    """The p fractile of the strengths ``y`` (N runs) under the lab fits,
    and its intervals.  ``inputs``: lab-fitted input -> its N values;
    ``sampling``: input -> the distribution the study drew it from;
    ``lab``: input -> (distribution, lab values, (mean*, cov*)) shared
    across levels.  Each replicate resamples the runs with replacement
    and weights them at theta*_b (both uncertainties); ``lab_only`` keeps
    every run once.  Returns the point (at the fits, every run), the
    interval, the lab-only interval and the ESS at the fits and over the
    replicates (median, 5 % quantile)."""
    y = np.asarray(y, float)
    g = np.random.default_rng(rng)
    idx = g.integers(0, y.size, (resamples, y.size))
    lw_hat = np.zeros(y.size)
    lw = np.zeros((resamples, y.size))
    for var, (dist, values, (m_b, c_b)) in lab.items():
        x = np.asarray(inputs[var], float)
        q = sampling[var].logpdf(x)
        lw_hat += density(dist, *moments(np.asarray(values, float))).logpdf(x) - q
        lw += density(dist, m_b[:, None], c_b[:, None]).logpdf(x[None, :]) - q
    w_hat = np.exp(lw_hat - lw_hat.max())
    w_lab = np.exp(lw - lw.max(-1, keepdims=True))
    w = np.take_along_axis(w_lab, idx, -1)
    both = weighted_fractile(y[idx], w, p, basis)
    lab_only = weighted_fractile(np.broadcast_to(y, w_lab.shape), w_lab, p, basis)
    ends = [50 * (1 - conf), 50 * (1 + conf)]
    e = ess(w)
    return {"point": float(weighted_fractile(y, w_hat, p, basis)), "interval": tuple(np.percentile(both, ends)),
            "lab_only": tuple(np.percentile(lab_only, ends)), "ess_point": float(ess(w_hat)),
            "ess_median": float(np.median(e)), "ess_05": float(np.quantile(e, 0.05)), "replicates": both}


def design_table(runs, level_column, inputs, sampling, lab, gamma_m, fxk2, as3700_inputs, rng, resamples=1000):
    """Per level of the ok runs: the wallette's characteristic flexural
    strength (MPa) with its interval (lab and runs), the lab-only and the
    runs-only intervals, the ESS, the design value f_xk / gamma_m, EN
    1996-1-1's f_xk2 (``fxk2``, MPa) and its design value, and AS 3700's
    capacities at the lab's characteristic values (``as3700_inputs``:
    (f'_mt, f'_ut) in MPa, or None where it does not apply).  ``inputs``:
    lab-fitted input -> its runs table column (SI = column x ``scale``)."""
    from .validation import as3700
    if not gamma_m > 0:
        raise InputError("design.gamma_M", f"{gamma_m}: a partial factor is above 0")
    ok = runs[runs.ok]
    boots = {v: (dist, vals, lab_resamples(vals, dist, resamples, g))
             for (v, (dist, vals)), g in zip(lab.items(), np.random.default_rng(rng).spawn(len(lab)))}
    rows = []
    for k, (level, group) in enumerate(ok.groupby(level_column)):
        y = group.strength_mpa.to_numpy(float)
        p_sw = fractiles.lognormal_fit(y)
        basis = "lognormal" if p_sw >= fractiles.NORMALITY_P else "non-parametric"
        x = {v: group[col].to_numpy(float) * scale for v, (col, scale) in inputs.items()}
        r = propagate(y, x, sampling, boots, np.random.default_rng([rng, k]), basis, resamples=resamples)
        runs_only = (fractiles.lognormal_fractile if basis == "lognormal" else fractiles.empirical_fractile)(y)
        row = {level_column: level, "runs": y.size, "basis": basis, "f_xk_mpa": r["point"],
               "f_xk_lo_mpa": r["interval"][0], "f_xk_hi_mpa": r["interval"][1],
               "lab_only_lo_mpa": r["lab_only"][0], "lab_only_hi_mpa": r["lab_only"][1],
               "runs_only_lo_mpa": runs_only[1], "runs_only_hi_mpa": runs_only[2],
               "ess": r["ess_point"], "ess_median": r["ess_median"], "ess_05": r["ess_05"],
               "gamma_M": gamma_m, "f_xd_mpa": r["point"] / gamma_m, "f_xk2_mpa": fxk2, "f_xd2_mpa": fxk2 / gamma_m}
        if as3700_inputs is not None:
            stepped, line = as3700(*as3700_inputs, np.array([level]))
            row.update(as3700_stepped_mpa=float(stepped[0]), as3700_line_mpa=float(line[0]))
        rows.append(row)
    return pd.DataFrame(rows)


def caption_lines(table, level_column, level_unit):
    """One line per level for the report page and the command's output."""
    out = []
    for r in table.to_dict("records"):
        rules = f"; EN 1996-1-1 f_xk2 {r['f_xk2_mpa']:.2f} MPa (design {r['f_xd2_mpa']:.3f})"
        if "as3700_stepped_mpa" in r and not math.isnan(r["as3700_stepped_mpa"]):
            rules += f"; AS 3700 stepped {r['as3700_stepped_mpa']:.3f}, line {r['as3700_line_mpa']:.3f} MPa"
        out.append(f"{r[level_column]:g} {level_unit}: f_xk {r['f_xk_mpa']:.3f} MPa ({r['f_xk_lo_mpa']:.3f} to "
                   f"{r['f_xk_hi_mpa']:.3f}; lab only {r['lab_only_lo_mpa']:.3f} to {r['lab_only_hi_mpa']:.3f}, "
                   f"runs only {r['runs_only_lo_mpa']:.3f} to {r['runs_only_hi_mpa']:.3f}; {r['basis']}, "
                   f"{r['runs']} runs, ESS {r['ess']:.1f}, median over resamples {r['ess_median']:.1f}), "
                   f"design f_xk / {r['gamma_M']:g} = {r['f_xd_mpa']:.3f} MPa" + rules)
    return out


def as3700_words(as3700, bond=None, units=None):
    """The design caption's words on AS 3700 (``as3700``: study_inputs'
    characteristic values, or None): its rules given at the lab's values,
    or why none are given (they need both the bond and the units' modulus
    of rupture from lab sheets: the config's design.bond and design.units)."""
    if as3700 is not None:
        return ("AS 3700's horizontal-bending rules (capacity factor 1) at the lab's characteristic flexural bond "
                "and unit modulus of rupture do")
    missing = " and ".join(f"design.{k} ({v or 'not set'})" for k, v in (("bond", bond), ("units", units)))
    return ("AS 3700's horizontal-bending rules, which do, need both the lab's flexural bond and its units' modulus "
            f"of rupture, each a variable fitted to a lab sheet ({missing}): none are given here")


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
