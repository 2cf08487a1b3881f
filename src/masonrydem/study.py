"""The stochastic study (docs/study.md, 8): from a sample to a scene.

Dependent quantities (docs/study.md, 3): c_j = 1.2 f_tj; G_fj,I = 0.03 f_tj and
G_fu = 0.04 f_tu^0.7 (N/mm with f in MPa), G_fj,II = 10 G_fj,I;
c_u = 1.5 f_tu; k_n from E_b, k_s = 0.4 k_n (the scene's rules).  In the
spatial variant a joint's k_n follows the mean E_b of the two units it
connects (specimen.build).
"""
import copy

import numpy as np

from .masonry import GF_COEFFICIENT, GF_EXPONENT, GI_PER_FT, unit_fracture_energy
from .scene import validate_scene


def study_scene(base, variant, sample, sigma_v):
    """The scene of one simulation: ``base`` (a validated scene dict) with
    the sample's properties and the precompression sigma_v (Pa).
    ``sample``: a mapping with f_tj, f_tu, phi_j, E_b (scalars for
    'nonspatial'; per unit f_tu, E_b and per joint f_tj, phi_j sequences for
    'spatial')."""
    sc = copy.deepcopy(base)
    sc["name"] = f"{base['name']}:{variant}:s{int(sample['sample'])}"
    mat = sc["materials"]
    if variant == "nonspatial":
        mat["units"].update(E=float(sample["E_b"]), ft=float(sample["f_tu"]),
                            Gf=float(unit_fracture_energy(sample["f_tu"])))
        mat["joints"].update(ft=float(sample["f_tj"]), phi=float(sample["phi_j"]),
                             GI=GI_PER_FT * float(sample["f_tj"]))
    elif variant == "spatial":
        mat["per_unit"] = dict(E=[float(x) for x in sample["E_b"]], ft=[float(x) for x in sample["f_tu"]],
                               gf_coefficient=GF_COEFFICIENT, gf_exponent=GF_EXPONENT)
        mat["per_joint"] = dict(ft=[float(x) for x in sample["f_tj"]], phi=[float(x) for x in sample["phi_j"]],
                                gi_per_ft=GI_PER_FT)
    else:
        raise ValueError(f"unknown variant {variant!r}")
    sc["loading"]["precompression"]["pressure"] = float(sigma_v)
    return validate_scene(sc)


def sample_inputs(sample):
    """The random inputs of one sample (a row of either table of
    sampling.study_samples) as a run's row reports them: E_b_mpa, f_tu_mpa,
    f_tj_mpa (MPa), phi_j_deg; the means over units and joints for the
    spatial variant.  For the row of a run that failed before its specimen
    existed."""
    return dict(E_b_mpa=float(np.mean(sample["E_b"])) / 1e6, f_tu_mpa=float(np.mean(sample["f_tu"])) / 1e6,
                f_tj_mpa=float(np.mean(sample["f_tj"])) / 1e6, phi_j_deg=float(np.mean(sample["phi_j"])))


def run_sample(base, sample, variant, sv_mpa, progress=True, frame=True):
    """One simulation of the study: ``sample`` (a mapping: its number and
    properties, a row of sampling.study_samples) of variant ``variant`` at
    the precompression ``sv_mpa`` (MPa) on the scene ``base``.  Returns
    runner.run_scene's (``frame``; else runner.simulate's) (row, curve,
    specimen, solver), the row labelled with variant, sample and
    sigma_v (and a curve frame too)."""
    from .runner import run_scene, simulate
    run = run_scene if frame else simulate
    row, curve, specimen, solver = run(study_scene(base, variant, sample, sv_mpa * 1e6), progress=progress)
    ids = dict(variant=variant, sample=int(sample["sample"]))
    if frame:
        curve = curve.assign(**ids, sigma_v_mpa=sv_mpa)
    return {**ids, **row, "sigma_v_mpa": sv_mpa}, curve, specimen, solver
