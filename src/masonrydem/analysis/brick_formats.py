"""The geometry study's equations on brick formats they were not fitted to
(docs/geometry-study.md): the out-of-format error.

A format is a study whose wallette has one brick (its scene, with the
geometry its rules set: config/studies/formats/*.yaml, the NF study, the
Willis study); its runs are predicted by the geometry study's predictor
(results/studies/geometry/study/predictor.json: the lower of its two
equations, whose terms name the brick's L, H, W and t in mm) and the error
is that of the prediction against the simulated strength, run by run.
Beside it, where a format has a predictor of its own (the Willis study's
fixed-geometry equations), that predictor's error on the same runs.
"""
import numpy as np
import pandas as pd

from . import equations as E

GEOMETRY = {"L": "geometry.unit.length", "H": "geometry.unit.height", "W": "geometry.unit.width",
            "t": "geometry.joint_thickness"}


def format_of(study_file):
    """(the brick of a study's wallette, {L, H, W, t} in mm: its scene's,
    with what the study's rules set; the variant its equations are fitted
    on)."""
    from ..scene import build_scene
    from ..study.file import load_study
    st = load_study(study_file)
    g = build_scene(st.scene, settings={k: v for k, v in st.rules.items() if k.startswith("geometry.")}).geometry
    return (dict(L=g.unit_length * 1e3, H=g.unit_height * 1e3, W=g.unit_width * 1e3, t=g.joint_thickness * 1e3),
            st.regression_variant)


def predictor_equations(predictor):
    """(joint, brick) equations of a predictor file's content
    (equations.joint_and_brick: with one mode fitted, it stands for both)."""
    return E.joint_and_brick({m: (e, None) for m, e in predictor["modes"].items()})


def _inputs(runs, predictor, geometry):
    """The predictor's inputs over the runs: its columns where the runs
    have them, else the format's constant brick (mm)."""
    out = {}
    for name, spec in predictor["inputs"].items():
        out[name] = (runs[spec["column"]].to_numpy(float) if spec["column"] in runs
                     else np.full(len(runs), float(geometry[name])))
    return out


def scores(runs, predictor, geometry, variant):
    """MAPE (%), mean error (bias, %) and the share of runs whose failure
    mode the predictor names, of a predictor on the ok runs of ``variant``."""
    ok = runs[runs.ok & (runs.variant == variant)]
    strength, mode = E.lower_of_two(*predictor_equations(predictor), _inputs(ok, predictor, geometry))
    y = ok.strength_mpa.to_numpy(float)
    return dict(runs=len(ok), mape_pct=E.mape(y, strength), bias_pct=float(100 * np.mean(strength / y - 1)),
                mode_agreement=float(np.mean(mode == ok.failure_mode.to_numpy())))


def held_out_table(predictor, formats, fitted_runs):
    """One row per format (name -> (runs, geometry, the variant its
    equations are fitted on, own predictor or None)): the format's brick,
    the geometry predictor's scores on its runs and, where it has one, its
    own predictor's; first the in-sample row, the geometry predictor on
    the runs it was fitted to (``fitted_runs``, of the predictor's
    variant)."""
    rows = [dict(format="fitted (in sample)", **scores(fitted_runs, predictor, {}, predictor["variant"]))]
    for name, (runs, geometry, variant, own) in formats.items():
        row = dict(format=name, **{f"{k}_mm": v for k, v in geometry.items()},
                   **scores(runs, predictor, geometry, variant))
        if own is not None:
            row.update({f"own_{k}": v for k, v in scores(runs, own, geometry, variant).items() if k != "runs"})
        rows.append(row)
    return pd.DataFrame(rows)


def caption_values(table, equations):
    """The caption's numbers: the equations, the in-sample and every
    format's error."""
    fitted, held = table.iloc[0], table.iloc[1:]
    lines = [f"{r.format} ({r.L_mm:g} x {r.W_mm:g} x {r.H_mm:g} mm, {r.t_mm:g} mm joints; {r.runs} runs): "
             f"MAPE **{r.mape_pct:.1f} %**, bias {r.bias_pct:+.1f} %, failure mode right in "
             f"{100 * r.mode_agreement:.0f} %" +
             (f"; its own fixed-geometry equations: MAPE {r.own_mape_pct:.1f} %, bias {r.own_bias_pct:+.1f} %"
              if "own_mape_pct" in table and pd.notna(r.own_mape_pct) else "")
             for r in held.itertuples()]
    return dict(equations="\n".join(f"- {e}" for e in equations), fitted_mape=f"{fitted.mape_pct:.1f}",
                fitted_runs=int(fitted.runs), held_mape=f"{held.mape_pct.max():.1f}",
                lines="\n".join(f"- {x}" for x in lines))
