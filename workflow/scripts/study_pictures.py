"""3-D pictures of typical study runs (captions.typical_run), each run
again with its final state (the rerun must repeat the recorded P_max
exactly: runs are bit-for-bit repeatable)."""
import sys

import numba

sm = snakemake  # noqa: F821
numba.set_num_threads(sm.threads)
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions, figures  # noqa: E402
from masonrydem.analysis.statistics import of_study  # noqa: E402
from masonrydem.pipeline.plan import level_override  # noqa: E402
from masonrydem.specimen.protocol import simulate  # noqa: E402
from masonrydem.specimen.row import outcome_row, read_json  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402
from masonrydem.specimen.state import state_blocks  # noqa: E402
from masonrydem.report.pictures import picture_damage  # noqa: E402

runs = pd.read_parquet(sm.input.runs)
level, _ = of_study(sm.params.analysis)
picked = []
for (variant, mode), path in zip(sm.params.pictures, sm.output.pictures):
    pick, at = captions.typical_run(runs, variant, mode, level)
    picked.append((variant, mode, pick, at))
    if pick is None:
        figures.placeholder(f"{variant}: no run failed in the {mode} mode", path)
        continue
    samples = read_json(sm.input.samples[sm.params.variants.index(variant)])
    sample = next(s for s in samples if s["sample"] == pick["sample"])
    at_level = level.text(pick[level.column])
    scene = build_scene(sm.input.scene, [*sm.params.overrides, level_override(sm.config, pick[level.column])],
                        sample["settings"], f"{variant}:s{pick['sample']}")
    outcome = simulate(scene, progress=False)
    row = outcome_row(outcome)
    if (row.P_max_kN, row.failure_mode) != (pick.P_max_kN, pick.failure_mode):
        raise RuntimeError(f"{variant} s{pick['sample']} at {at_level}: the rerun gives P_max "
                           f"{row.P_max_kN} kN ({row.failure_mode}), the study recorded {pick.P_max_kN} kN "
                           f"({pick.failure_mode})")
    picture_damage(state_blocks(outcome.specimen, outcome.state), path, title=f"{variant} sample {pick['sample']}, "
                   f"{level.name} = {at_level}: P_max {pick.P_max_kN:.2f} kN, {mode} failure",
                   window=figures.PICTURE_WINDOW, rig=scene.loading.bending)
captions.write_caption(sm.input.template, sm.output.caption, **captions.study_pictures(picked, level))
