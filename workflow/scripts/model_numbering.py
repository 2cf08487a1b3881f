"""The model with its units and joints numbered."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

from masonrydem.report.figures import PICTURE_WINDOW  # noqa: E402
from masonrydem.scene import build_scene  # noqa: E402
from masonrydem.specimen.build import build  # noqa: E402
from masonrydem.report.pictures import picture_numbering  # noqa: E402

specimen = build(build_scene(sm.input.scene))
picture_numbering(specimen, sm.output[0], window=PICTURE_WINDOW)
print(f"{len(specimen.units)} units, {len(specimen.joints)} joints")
