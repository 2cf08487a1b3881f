"""A study's prediction equations as a tool: ``masonrydem predict`` and
``predict()``.

The study's regression (workflow/scripts/regression.py) writes a
predictor file (results/study/predictor.json): the Lasso equation of each
failure mode (the strength in MPa, a function of the terms the study file
names), the inputs the equations use with their units, the range of each
they were fitted on, the wallette they hold for (its
section, thickness and shear span, to turn a strength into a load), and
each equation's out-of-fold residuals, as simulated over predicted
strength: the error on a wallette the fit had not seen (nested 5-fold
cross-validation, folds of whole samples).

``predict`` evaluates both equations; the lower one governs (the lower of
two, as the study scores it) and names the failure mode.  Each mode's 95 %
interval is its predicted strength times the 2.5 and 97.5 % quantiles of
its out-of-fold ratios; the wallette's strength being the lower of its two
modes' strengths, each bound of its prediction interval is the lower of the
two modes' bounds (``_interval``).  Inputs outside the fitted range are
refused: the equations are a fit over that range, nothing more.
"""
import json
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..scene import is_plain, meant, shown, to_shown, to_si

def build(fits, ns, scene, source, columns, units, variant, settings=None, study=None, level=None,
          skipped=None, labs=None):
    """The predictor of the fitted equations ``fits`` (equations.
    prediction_equations: mode -> (equation, strengths)) on the runs
    ``ns``, for the wallette of the typed ``scene``; ``source``: where the
    runs came from (named in the printout); ``columns`` and ``units``: each
    input's column in ``ns`` and its SI unit (Study.columns, Study.units);
    ``variant``: the study's variant the runs are of; ``settings``: the
    scene setting each random input drives (where the scene's section is
    the wall as built and its spans are in unit lengths, both follow a
    brick that the inputs change: ``wallette_at``); ``study``: the study's
    name;
    ``level``: its swept input's name, whose levels' shares of each
    failure mode among the runs are kept (``predict`` warns where a mode
    it has no equation for occurs); ``skipped``: mode -> why it has no
    equation; ``labs``: input -> its lab fit's conversion (lab_conversions),
    so that a lab's value and the model's are shown side by side."""
    from ..study.terms import parse_term
    used = dict.fromkeys(name for eq, _ in fits.values() for term in eq["coef"] for name in parse_term(term, units)[1])
    g, bend = scene.geometry, scene.loading.bending
    modes = {}
    for mode, (eq, _) in fits.items():
        g_mode = ns[ns.failure_mode == mode]
        ratio = g_mode.strength_mpa.to_numpy() / eq["cv_predicted"]
        modes[mode] = dict(intercept=eq["intercept"], coef=eq["coef"], n=eq["n"], cv_mape_pct=eq["cv_mape"],
                           ratio_q025=float(np.quantile(ratio, 0.025)), ratio_q975=float(np.quantile(ratio, 0.975)))
    shares = {}
    if level is not None and len(ns):
        for x, at in ns.groupby(columns[level]):
            shares[repr(float(x))] = {m: float((at.failure_mode == m).mean()) for m in ("joint", "brick")}
    return dict(
        source=source, study=study, scene=scene.name, variant=variant, modes=modes, skipped=dict(skipped or {}),
        level=level, mode_shares=shares,
        inputs={name: dict(unit=units[name], shown=shown(units[name])[0], column=columns[name],
                            **({"setting": settings[name]} if name in (settings or {}) else {}),
                            **({"lab": labs[name]} if name in (labs or {}) else {})) for name in used},
        fitted_range={name: [float(ns[columns[name]].min()), float(ns[columns[name]].max())] for name in used},
        wallette=dict(courses=g.courses, units_per_course=g.units_per_course,
                      unit_mm=[g.unit_length * 1e3, g.unit_height * 1e3, g.unit_width * 1e3],
                      joint_mm=g.joint_thickness * 1e3, section_height_m=bend.section,
                      thickness_m=g.unit_width, shear_span_m=bend.shear_span,
                      section_as_built=bend.section_as_built, spans_in_units=bend.spans_in_units,
                      **({"direction": "vertical", "bed_units": (g.common_span[1] - g.common_span[0]) / g.modelled_unit[0]}
                         if bend.direction == "vertical" else {})))


def lab_conversions(provenance):
    """Input -> (factor, the lab's quantity, the conversion's source) of a
    study's lab-fitted variables (Study.provenance: masonrydem fit's
    records): the model's value is the factor times the lab's."""
    return {name: dict(factor=r["conversion"]["factor"], quantity=r["lab"]["quantity"],
                       source=r["conversion"]["source"]) for name, r in provenance.items()}


def cite(source):
    """A conversion's source as a short citation: its text before the first
    comma ('EN 1992-1-1:2004')."""
    return source.split(",")[0]


def _as_lab(value, spec):
    """' (the lab's flexural bond strength 0.3453 MPa x 0.6667, EN ...)'
    for a lab-fitted input, else ''."""
    lab = spec.get("lab")
    if not lab:
        return ""
    return (f" (the lab's {lab['quantity']} {value / lab['factor']:.4g} {spec['shown']} x {lab['factor']:.4g}: "
            f"{cite(lab['source'])})")


BRICK = ("geometry.unit.length", "geometry.unit.height", "geometry.unit.width", "geometry.joint_thickness")


def wallette_at(p, x):
    """The predictor's wallette with the brick the inputs ``x`` (in the
    units shown) give, where they drive its size: its thickness is the
    brick's width, and its section (the wall as built) and shear span (in
    unit lengths) follow the brick where the scene gave them so."""
    w = dict(p["wallette"])
    given = {spec["setting"]: x[name] * shown(spec["unit"])[1] for name, spec in p["inputs"].items()
             if spec.get("setting") in BRICK}
    if not given:
        return w
    before = [v / 1e3 for v in w["unit_mm"]] + [w["joint_mm"] / 1e3]
    L, H, W, t = (given.get(k, v) for k, v in zip(BRICK, before))
    vertical = w.get("direction") == "vertical"     # the section across the courses, the span along them
    if w.get("section_as_built"):
        w["section_height_m"] = w["bed_units"] * (L + t) - t if vertical else w["courses"] * H + (w["courses"] - 1) * t
    if w.get("spans_in_units"):
        w["shear_span_m"] *= (H + t) / (before[1] + before[3]) if vertical else (L + t) / (before[0] + before[3])
    w.update(unit_mm=[L * 1e3, H * 1e3, W * 1e3], joint_mm=t * 1e3, thickness_m=W, brick_from_inputs=True)
    return w


def _value(eq, x):
    from .equations import predict as evaluate
    return float(evaluate(eq, x).item())


@dataclass(frozen=True)
class Prediction:
    strength_mpa: float         # the governing (lower) equation's
    mode: str                   # joint or brick
    interval_mpa: tuple         # 95 % prediction interval
    load_kN: float              # P: the total of the two line loads
    interval_kN: tuple
    by_mode: dict               # mode -> strength (MPa)
    inputs: dict                # input -> its value in the unit shown (MPa, mm, deg)
    units: dict                 # input -> that unit
    wallette: dict
    source: str
    warnings: tuple = ()        # what the answer cannot vouch for (a mode without its equation)
    specs: dict = None          # input -> the predictor's record of it (its lab conversion, if any)

    def lines(self):
        w = self.wallette
        which = "for this brick's wallette" if w.get("brick_from_inputs") else "for the wallette they were fitted on"
        if w.get("direction") == "vertical":
            which += " in vertical bending (plane of failure parallel to the bed joints: f_x1)"
        out = ["the strength of one wallette with these properties, by a study's prediction equations: not a mean "
               "strength and not a characteristic (5 %) value, which the study's statistics and characteristic "
               "tables give",
               f"the equations of {self.source}, {which}: {_wallette(w)}; section "
               f"b = {w['section_height_m']:g} m, thickness h = {w['thickness_m']:g} m, shear span a = "
               f"{w['shear_span_m']:.4g} m (sigma = 6 M / (b h^2), M = P a / 2)",
               "  " + ", ".join(f"{k} {v:g} {self.units[k]}".rstrip() + _as_lab(v, (self.specs or {}).get(k, {}))
                                for k, v in self.inputs.items())]
        out += [f"  {m} failure: {s:.3f} MPa" for m, s in self.by_mode.items()]
        lo, hi = self.interval_mpa
        out.append(f"governing: {self.mode} failure, strength {self.strength_mpa:.3f} MPa (95 % prediction interval "
                   f"{lo:.3f} to {hi:.3f} MPa), load P = {self.load_kN:.2f} kN ({self.interval_kN[0]:.2f} to "
                   f"{self.interval_kN[1]:.2f} kN)")
        out += [f"WARNING: {x}" for x in self.warnings]
        return out


def _wallette(w):
    unit = " x ".join(f"{x:g}" for x in w["unit_mm"])
    return f"{w['courses']} courses x {w['units_per_course']} units of {unit} mm, joints {w['joint_mm']:g} mm"


def load(path):
    try:
        with open(path) as f:
            p = json.load(f)
    except OSError as e:
        raise InputError("predictor", f"cannot read {path}: {e.strerror} (the study's regression writes it: "
                                    "snakemake --cores 2 results/study/predictor.json)") from None
    except ValueError as e:
        raise InputError("predictor", f"{path} is not a predictor file: {e}") from None
    if "inputs" not in p:
        raise InputError("predictor", f"{path} is a predictor of an older version (it does not name its inputs): "
                                    "rerun the study's regression, which writes it")
    return p


def predict(study, options=None, scene=None, **inputs):
    """The prediction at the ``inputs`` the equations use (texts, as a user
    types them, with their units: '3.5 MPa'; numbers: SI); ``study``: a
    predictor file or its mapping (build); ``options``: input -> how the
    caller named it (in errors; the input's name by default); ``scene``:
    the typed scene of the user's wallette, refused unless it is the one
    the equations were fitted on."""
    p = load(study) if isinstance(study, str) else study
    source = p["source"] if isinstance(study, dict) else f"{study} ({p['source']})"
    if p.get("study"):
        source = f"the study {p['study']!r}: {source}"
    if scene is not None:
        _same_wallette(p, scene)
    options = options or {}
    unknown = sorted(set(inputs) - set(p["inputs"]))
    if unknown:
        raise InputError(options.get(unknown[0], unknown[0]), f"the equations have no input {unknown[0]!r}: they "
                                                               f"take {', '.join(p['inputs'])}")
    x = {name: _checked(p, name, spec, inputs, options.get(name, name)) for name, spec in p["inputs"].items()}
    by_mode = {m: _value(eq, x) for m, eq in p["modes"].items()}
    mode = min(by_mode, key=by_mode.get)
    s = by_mode[mode]
    w = wallette_at(p, x)
    to_kN = w["section_height_m"] * w["thickness_m"] ** 2 / 6.0 / (0.5 * w["shear_span_m"]) * 1e3  # MPa -> kN
    interval = _interval(p["modes"], by_mode)
    return Prediction(strength_mpa=s, mode=mode, interval_mpa=interval, load_kN=s * to_kN,
                      interval_kN=tuple(v * to_kN for v in interval), by_mode=by_mode, inputs=x,
                      units={k: spec["shown"] for k, spec in p["inputs"].items()},
                      wallette=w, source=source, warnings=tuple(_warnings(p, x, by_mode)), specs=p["inputs"])


def _interval(modes, by_mode):
    """The 95 % prediction interval of the lower of two: each bound the
    lower of the modes' bounds, a mode's bounds being its strength
    ``by_mode`` times the 2.5 and 97.5 % quantiles of its out-of-fold
    ratios.  The strength y = min(y_joint, y_brick) is at most either, so y
    exceeds the upper bound with a chance of at most 2.5 %; it falls below
    the lower bound with a chance between 2.5 % and 5 %, 2.5 % where one
    mode's interval lies well below the other's.  The governing mode's
    interval alone (the lower mode's strength times its own ratios) leaves
    out the other mode's scatter where the two are close: a wallette
    predicted to fail in its joints may fail in its bricks, below that
    interval (the Willis study's runs within 10 % of the crossing where the
    joint equation governs: 87 % inside it, 92 % inside this one;
    tests/test_check_predict.py, on two known noisy laws)."""
    return tuple(min(by_mode[m] * modes[m][q] for m in by_mode) for q in ("ratio_q025", "ratio_q975"))


def _warnings(p, x, by_mode):
    """A failure mode without its equation: what the answer then cannot
    vouch for, and how often the study's runs failed so near these inputs
    (at the nearest level of its swept input)."""
    out = []
    for mode in ("joint", "brick"):
        if mode in by_mode:
            continue
        why = p.get("skipped", {}).get(mode, "too few runs failed in it")
        line = (f"no {mode}-failure equation ({why}): the answer is the {next(iter(by_mode))} equation's, too high "
                f"wherever the {mode} mode governs")
        shares, level = p.get("mode_shares") or {}, p.get("level")
        if shares and level in x:
            nearest = min(shares, key=lambda k: abs(float(k) - x[level]))
            share = shares[nearest][mode]
            line += (f"; {share:.0%} of the study's runs at {level} = {float(nearest):g} "
                     f"{p['inputs'][level]['shown']} failed in the {mode} mode").rstrip()
        out.append(line)
    return out


def _same_wallette(p, scene):
    """Refuses a scene whose wallette is not the one the equations were
    fitted on (its bricks where the equations do not take their size as
    inputs, its courses and units in any case)."""
    w, g = p["wallette"], scene.geometry
    brick_inputs = any(spec.get("setting") in BRICK for spec in p["inputs"].values())
    mine = dict(courses=g.courses, units_per_course=g.units_per_course, joint_mm=g.joint_thickness * 1e3,
                unit_mm=[g.unit_length * 1e3, g.unit_height * 1e3, g.unit_width * 1e3])
    keys = ("courses", "units_per_course") if brick_inputs else ("courses", "units_per_course", "unit_mm", "joint_mm")
    if any(not np.allclose(mine[k], w[k], rtol=1e-9) for k in keys):
        raise InputError("--scene", f"its wallette ({_wallette(mine)}) is not the one these equations were fitted on "
                                    f"({_wallette(w)}): their answer would not hold for it.  Fit equations on your "
                                    "own wallette (a study file of your scene: docs/your-own-study.md), or use a "
                                    "predictor whose inputs include the brick's size (the geometry study's: "
                                    "results/studies/geometry/study/predictor.json)")


def _lab_hint(name, x, spec):
    """Where a refused input is lab-fitted: how a lab's value becomes the
    model's (a lab value typed where the model's is asked for is the
    likeliest slip)."""
    lab = spec.get("lab")
    if not lab:
        return ""
    return (f"; {name} is the model's value, {lab['factor']:.4g} x the lab's {lab['quantity']} "
            f"({cite(lab['source'])}): a lab value of {x:.4g} {spec['shown']} is {name} = "
            f"{x * lab['factor']:.4g} {spec['shown']}")


def _checked(p, name, spec, inputs, option):
    """The input ``name`` in the unit shown, refused outside the fitted range."""
    if name not in inputs:
        raise InputError(option, f"missing: the equations take {', '.join(p['inputs'])}")
    value, unit = inputs[name], spec["unit"]
    if unit and isinstance(value, str) and is_plain(value) and float(value) != 0:
        raise InputError(option, f"{value!r} has no unit, and {name} is a quantity: did you mean "
                                 f"'{float(value):g} {spec['shown']}'?")
    x = to_shown(to_si(value, unit, option), unit)
    lo, hi = p["fitted_range"][name]
    if not lo <= x <= hi:
        plain = is_plain(value)
        size = shown(unit)[1]
        guess = meant(float(value), unit, lo * size, hi * size) if plain else None
        raise InputError(option, f"{f'{float(value):g} {unit}'.rstrip() if plain else value} is outside the range "
                                 f"the equations were fitted on, {lo:.3g} to {hi:.3g} {spec['shown']}".rstrip()
                         + (f": did you mean {guess}?" if guess else "") + _lab_hint(name, x, spec)
                         + f" (they hold only there, and only for the wallette of the scene {p['scene']!r}: "
                         f"{_wallette(p['wallette'])})")
    return x


def both_directions(predictor, other, options, scene, inputs):
    """The lines ``predict`` prints: one study's prediction, or with
    ``other`` (the same study's predictor in the other bending direction)
    both, and the orthogonal ratio mu = f_x1 / f_x2 of the governing
    strengths.  A study's directions table (directions.csv) gives mu per
    level with its interval from the pairs of runs."""
    first = predict(predictor, options, scene, **inputs)
    if other is None:
        return first.lines()
    second = predict(other, options, None, **inputs)
    dirs = [p.wallette.get("direction", "horizontal") for p in (first, second)]
    if len(set(dirs)) == 1:
        raise InputError("--other", f"{other} bends {dirs[1]}ly, as {predictor} does: give the same study's "
                                    "predictor in the other direction")
    by = dict(zip(dirs, (first, second)))
    mu = by["vertical"].strength_mpa / by["horizontal"].strength_mpa
    return ([*by["horizontal"].lines(), *by["vertical"].lines()] +
            [f"mu = f_x1 / f_x2 = {by['vertical'].strength_mpa:.3f} / {by['horizontal'].strength_mpa:.3f} = "
             f"{mu:.3f} (of these governing strengths; its interval from the study's pairs of runs: its "
             "directions table)"])
