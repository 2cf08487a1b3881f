"""The stochastic study (docs/study.md, 8): a sample as scene settings.

A study file (studyfile.py) names the scene setting each random variable
drives and the settings that follow from them (its rules).  A sample's
record carries its settings (``settings``, written with the samples by
the workflow's sample rule), so that a job applies them without reading
the study file: one value of each variable for the wallette (a variant
that draws per 'wallette'), or one per unit or joint ('items': the
setting's per-unit or per-joint list, materials.per_unit.E and so on).
The scene applies the rules item by item (masonry.py): for the Willis
study G_fu = 0.04 f_tu^0.7 (N/mm with f in MPa) and G_I = 0.03 f_tj (N/mm
per MPa); c_u = 1.5 f_tu, c_j = 1.2 f_tj, G_II = 10 G_I, k_n from E_b and
k_s = 0.4 k_n.
"""
from .masonry import GF_COEFFICIENT, GF_EXPONENT, GI_PER_FT

VARIANTS = ("nonspatial", "spatial")
# the Willis study's variants and rules (config/studies/willis.yaml)
WILLIS_DRAWS = {"nonspatial": "wallette", "spatial": "items"}
WILLIS_RULES = {"materials.units.Gf_rule": {"coefficient": GF_COEFFICIENT, "exponent": GF_EXPONENT},
                "materials.joints.GI_per_ft": GI_PER_FT, "materials.units.c_ratio": 1.5,
                "materials.joints.c_ratio": 1.2, "materials.joints.GII_ratio": 10.0,
                "materials.joints.Em_ratio": 0.1, "materials.joints.ks_ratio": 0.4}
PER_ITEM = {"unit": ("materials.units.", "materials.per_unit."), "joint": ("materials.joints.", "materials.per_joint.")}


def settings(sample, draw, variables, rules):
    """The scene settings (dotted path -> value) of one sample record
    (its number and each variable's value: a scalar for draw 'wallette', a
    sequence per unit or joint for 'items' and 'field'), with the study's
    ``rules``."""
    if draw not in ("wallette", "items", "field"):
        raise ValueError(f"unknown draw {draw!r}: wallette, items or field")
    out = {}
    for v in variables:
        if draw == "wallette":
            out[v.setting] = float(sample[v.name])
        else:
            wall, item = PER_ITEM[v.per]
            out[item + v.setting[len(wall):]] = [float(x) for x in sample[v.name]]
    return {**out, **rules}


def willis_record(sample, variant):
    """A sample of the Willis study with its settings (tests, benchmarks)."""
    from .sampling import STUDY_VARIABLES
    if variant not in WILLIS_DRAWS:
        raise ValueError(f"unknown variant {variant!r}: one of {', '.join(VARIANTS)}")
    return {**sample, "settings": settings(sample, WILLIS_DRAWS[variant], STUDY_VARIABLES, WILLIS_RULES)}


def sample_inputs(sample):
    """The random inputs of one sample as a run's row reports them: E_b_mpa,
    f_tu_mpa, f_tj_mpa (MPa), phi_j_deg; the means over units and joints for
    the spatial variant (the row of a sample the scene refused)."""
    import numpy as np
    return dict(E_b_mpa=float(np.mean(sample["E_b"])) / 1e6, f_tu_mpa=float(np.mean(sample["f_tu"])) / 1e6,
                f_tj_mpa=float(np.mean(sample["f_tj"])) / 1e6, phi_j_deg=float(np.mean(sample["phi_j"])))


def apply_sample(scene, sample, variant):
    """The scene mapping (not yet validated) with a sample record's settings
    and the name '<scene>:<variant>:s<sample>'."""
    import copy

    from .inputs import set_value
    if "settings" not in sample:
        raise ValueError(f"sample {sample.get('sample')} has no settings: a samples file of an older version; "
                         "rerun the study's sample rule")
    for key, value in sample["settings"].items():
        set_value(scene, key, copy.deepcopy(value))
    scene["name"] = f"{scene.get('name', 'scene')}:{variant}:s{int(sample['sample'])}"
    return scene


def study_scene(path, overrides, sample, variant):
    """The typed scene of one study simulation: the scene file at ``path``,
    its ``overrides`` ('path.to.key=value'), then the sample's settings."""
    from .inputs import apply_overrides, read_scene
    from .scene import validate_scene
    return validate_scene(apply_sample(apply_overrides(read_scene(path), overrides), sample, variant))
