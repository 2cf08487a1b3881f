"""The stochastic study (docs/study.md, 8): a sample as scene settings.

A sample sets the units' E and f_tu and the joints' f_tj and phi_j: once
for the wallette (variant 'nonspatial') or one value per unit and per
joint ('spatial').  Both variants declare the same dependent rules
(docs/study.md, 3), which the scene applies item by item (masonry.py):
G_fu = 0.04 f_tu^0.7 (N/mm with f in MPa) and G_I = 0.03 f_tj (N/mm per
MPa); c_u = 1.5 f_tu, c_j = 1.2 f_tj, G_II = 10 G_I, k_n from E_b and
k_s = 0.4 k_n are the scene's own ratios.
"""
from .masonry import GF_COEFFICIENT, GF_EXPONENT, GI_PER_FT

VARIANTS = ("nonspatial", "spatial")


def sample_settings(sample, variant):
    """The scene settings (dotted path -> value) of one sample (a mapping:
    its number and properties, a record of sampling.study_samples; scalars
    for 'nonspatial', per unit f_tu, E_b and per joint f_tj, phi_j sequences
    for 'spatial')."""
    rules = {"materials.units.Gf_rule": {"coefficient": GF_COEFFICIENT, "exponent": GF_EXPONENT},
             "materials.joints.GI_per_ft": GI_PER_FT}
    if variant == "nonspatial":
        values = {"materials.units.E": float(sample["E_b"]), "materials.units.ft": float(sample["f_tu"]),
                  "materials.joints.ft": float(sample["f_tj"]), "materials.joints.phi": float(sample["phi_j"])}
    elif variant == "spatial":
        values = {f"materials.per_{what}.{key}": [float(x) for x in sample[name]]
                  for what, key, name in (("unit", "E", "E_b"), ("unit", "ft", "f_tu"), ("joint", "ft", "f_tj"),
                                          ("joint", "phi", "phi_j"))}
    else:
        raise ValueError(f"unknown variant {variant!r}: one of {', '.join(VARIANTS)}")
    return {**values, **rules}


def sample_inputs(sample):
    """The random inputs of one sample as a run's row reports them: E_b_mpa,
    f_tu_mpa, f_tj_mpa (MPa), phi_j_deg; the means over units and joints for
    the spatial variant (the row of a sample the scene refused)."""
    import numpy as np
    return dict(E_b_mpa=float(np.mean(sample["E_b"])) / 1e6, f_tu_mpa=float(np.mean(sample["f_tu"])) / 1e6,
                f_tj_mpa=float(np.mean(sample["f_tj"])) / 1e6, phi_j_deg=float(np.mean(sample["phi_j"])))


def apply_sample(scene, sample, variant):
    """The scene mapping (not yet validated) with a sample's settings and
    the name '<scene>:<variant>:s<sample>'."""
    from .inputs import set_value
    for key, value in sample_settings(sample, variant).items():
        set_value(scene, key, value)
    scene["name"] = f"{scene.get('name', 'scene')}:{variant}:s{int(sample['sample'])}"
    return scene


def study_scene(path, overrides, sample, variant):
    """The typed scene of one study simulation: the scene file at ``path``,
    its ``overrides`` ('path.to.key=value'), then the sample's settings."""
    from .inputs import apply_overrides, read_scene
    from .scene import validate_scene
    return validate_scene(apply_sample(apply_overrides(read_scene(path), overrides), sample, variant))
