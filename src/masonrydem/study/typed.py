"""The typed study: ``Study``, a study file read and checked (file.py),
and its samples, drawn by ``Study.draw`` alone (``Draw``)."""
import hashlib
import json
from dataclasses import asdict, dataclass, field, replace
from functools import cached_property

import numpy as np

from ..errors import InputError
from ..scene import PRECOMPRESSION, build_scene, column, shown, to_shown
from .sampling import field_samples, item_samples, records, wallette_samples
from .settings import record


@dataclass(frozen=True)
class Study:
    name: str
    scene: str                 # the scene file
    samples: int
    seed: int
    variables: tuple           # sampling.Variable, in the file's order
    correlations: dict         # (name, name) -> rho
    variants: dict             # name -> {'draw': wallette, items or field, 'correlation_length': m or None}
    rules: dict                # dotted scene setting -> value
    sweep_setting: str
    levels: tuple              # SI
    features: tuple            # the equations' terms (study/terms.py)
    sweep_name: str            # the swept setting's name as an input
    units: dict                # input (a variable or the sweep's name) -> its SI unit
    regression_variant: str = None   # the variant the equations are fitted on (None: none fitted)
    provenance: dict = field(default_factory=dict)   # variable -> its lab fit's record (masonrydem fit)
    directions: dict = field(default_factory=dict)   # bending direction -> its scene file, the scene's own included
    direction: str = None      # the direction this study runs (its scene's): directions[direction] == scene

    def in_direction(self, direction):
        """The study in another bending direction: the same samples (draws
        per wallette, so each sample's material is the same in both: the
        runs pair), on that direction's scene."""
        if direction not in self.directions:
            raise InputError("direction", f"the study {self.name!r} has no specimen for {direction} bending; its "
                                          f"directions: {', '.join(self.directions)} (the study file's directions)")
        return replace(self, scene=self.directions[direction], direction=direction)

    def variable(self, name):
        return next(v for v in self.variables if v.name == name)

    def column(self, name):
        """The runs table's column of an input (a variable, or the swept
        setting by its name): the name and the unit it is shown in,
        f_tj_mpa, sigma_v_mpa, t_mm."""
        return column(name, self.units[name])

    def columns(self):
        """Input -> its column, the variables' and the sweep's."""
        return {name: self.column(name) for name in self.units}

    def level_column(self):
        return self.column(self.sweep_name)

    def means(self):
        """Each variable's mean (its distribution's, where the file gives
        none) in the unit the runs table shows it in."""
        return {v.name: to_shown(mean_of(v), self.units[v.name]) for v in self.variables}

    def per(self, what):
        """The variables carried per unit or per joint, in the file's order."""
        return tuple(v for v in self.variables if v.per == what)

    def mean_settings(self):
        """The scene settings of the wallette of mean properties: the rules
        and each variable at its mean (its distribution's, where the file
        gives none)."""
        return {**self.rules, **{v.setting: mean_of(v) for v in self.variables}}

    @property
    def sweeps_precompression(self):
        """Whether the swept setting is the vertical precompression (the
        design rules are functions of it)."""
        return self.sweep_setting == PRECOMPRESSION

    def level_unit(self):
        """The unit the runs table shows the swept setting in (MPa)."""
        return shown(self.units[self.sweep_name])[0]

    def items(self):
        """The study's wallette (its scene with the study's rules): its
        units' and joints' centres, each an (x, z) on the wall's face (m),
        in the order of the per-unit and per-joint settings."""
        centres = build_scene(self.scene, settings=self.rules).geometry.item_centres()
        return {what: np.asarray(centres[what], float).reshape(-1, 2) for what in ("unit", "joint")}

    def draw(self, variant):
        """The samples of ``variant`` (a ``Draw``): the one place a study's
        samples are drawn, reproducible from its seed (sampling.py: one
        value per wallette, per unit and joint, or random fields, as the
        variant says).  Its levels play no part: a new level draws the same
        samples."""
        if variant not in self.variants:
            raise InputError("variant", f"the study {self.name!r} has no variant {variant!r}; its variants: "
                                        f"{', '.join(self.variants)}")
        how, length = self.variants[variant]["draw"], self.variants[variant]["correlation_length"]
        wallettes, achieved = self.wallette_draw
        if how == "items":
            items = self.items()
            table = item_samples(self.samples, self.seed, len(items["unit"]), len(items["joint"]), self.variables,
                                 self.correlations)
        elif how == "field":
            table = field_samples(self.samples, self.seed, self.variables, self.correlations, self.items(), length)
        else:
            table = wallettes.copy()      # the draw is the study's: a caller may change its copy
        return Draw(variant, how, length, table, achieved, self.variables, self.rules)

    @cached_property
    def wallette_draw(self):
        """(the Latin Hypercube draw of one value per wallette: sample and
        each variable's value, SI; its achieved Pearson correlations), the
        draw of every variant's 'wallette' samples (sampling.py)."""
        return wallette_samples(self.samples, self.seed, self.variables, self.correlations)

    def draw_key(self):
        """A digest of everything that decides the samples (not the
        levels): the workflow's sample rules take it as a parameter."""
        items = {k: v.tolist() for k, v in self.items().items()}
        decisive = [self.samples, self.seed, [asdict(v) for v in self.variables],
                    sorted([a, b, rho] for (a, b), rho in self.correlations.items()), self.variants, self.rules, items]
        return hashlib.sha256(json.dumps(decisive, sort_keys=True, default=str).encode()).hexdigest()[:16]

    def pick_freeze(self, base, seed):
        """Saltelli's pick-freeze points of the study's variables
        (copula.pick_freeze) as sample records of a variant that draws one
        value per wallette, numbered in SALib's order."""
        from .copula import pick_freeze      # scipy.stats and SALib: on first use
        _, x = pick_freeze(self.variables, self.correlations, base, seed)
        points = [{"sample": k, **{v.name: float(x[k, j]) for j, v in enumerate(self.variables)}}
                  for k in range(len(x))]
        return [record(p, "wallette", self.variables, self.rules) for p in points]


@dataclass(frozen=True)
class Draw:
    """A variant's samples: ``table`` (sample and each variable's value, or
    its values per unit or joint, SI), how they were drawn, and the
    achieved Pearson correlations of the study's one-per-wallette draw."""
    variant: str
    how: str                  # wallette, items or field
    correlation_length: float  # m, of a field; else None
    table: object             # a DataFrame
    achieved: np.ndarray
    variables: tuple
    rules: dict

    def records(self):
        """The samples as a samples file holds them: each its number, its
        values, its scene settings and each variable's setting
        (settings.record)."""
        return [record(r, self.how, self.variables, self.rules) for r in records(self.table)]

    def describe(self):
        return {"wallette": "one draw per wallette", "items": "one draw per unit and joint",
                "field": f"random fields, correlation length {self.correlation_length} m"}[self.how]


def mean_of(v):
    """A variable's mean: the file's, else its distribution's (scipy.stats,
    loaded only then)."""
    return v.mean if v.mean is not None else float(v.frozen().mean())
