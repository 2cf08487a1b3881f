"""The cracked, deformed state of one run, rendered off screen."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402
import pyvista as pv  # noqa: E402

from masonrydem.report.figures import PICTURE_WINDOW  # noqa: E402
from masonrydem.report.pictures import picture_damage  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402

row = pd.read_parquet(sm.input.result).iloc[0]
title = (f"{row['scene']}, sigma_v = {row['sigma_v_mpa']:.3g} MPa: P_max {row['P_max_kN']:.2f} kN, "
         f"{row['failure_mode']} failure")
print("magnification", picture_damage(pv.read(sm.input.state), sm.output[0], title=title, window=PICTURE_WINDOW,
                                     rig=build_scene(sm.input.scene, sm.params.overrides).loading.bending))
