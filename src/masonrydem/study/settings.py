"""A study's sample as scene settings (docs/study.md, 8).

A study file (file.py) names the scene setting each random variable
drives and the settings that follow from them (its rules).  A sample's
record carries its settings (``settings``) and the setting of each of
the study's variables (``inputs``), both written with the samples by the
workflow's sample rule, so that a job applies them and reports the
study's inputs without reading the study file: one value of each
variable for the wallette (a variant that draws per 'wallette'), or one
per unit or joint ('items' and 'field': the setting's per-unit or
per-joint list, materials.per_unit.E and so on).  The scene applies the
rules item by item (scene/masonry.py).

Nothing here needs the solver: the samples do not depend on it.
"""
PER_ITEM = {"unit": ("materials.units.", "materials.per_unit."), "joint": ("materials.joints.", "materials.per_joint.")}
DRAWS = ("wallette", "items", "field")


def settings(sample, draw, variables, rules):
    """The scene settings (dotted path -> value) of one sample record
    (its number and each variable's value: a scalar for draw 'wallette', a
    sequence per unit or joint for 'items' and 'field'), with the study's
    ``rules``."""
    if draw not in DRAWS:
        raise ValueError(f"unknown draw {draw!r}: {', '.join(DRAWS)}")
    out = {}
    for v in variables:
        if draw == "wallette":
            out[v.setting] = float(sample[v.name])
        else:
            wall, item = PER_ITEM[v.per]
            out[item + v.setting[len(wall):]] = [float(x) for x in sample[v.name]]
    return {**out, **rules}


def record(sample, draw, variables, rules):
    """A sample's record as the samples file holds it: its number and
    values, its scene settings (``settings``) and each variable's setting
    by the variable's name (``inputs``: what the run's row reports)."""
    return {**sample, "settings": settings(sample, draw, variables, rules),
            "inputs": {v.name: v.setting for v in variables}}
