"""Latin Hypercube samples of the study's variants (their check:
sampling_check.py), each record with the scene settings it gives
(study.settings): a job applies them without the study file."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

from masonrydem import plan  # noqa: E402
from masonrydem.results import write_json  # noqa: E402
from masonrydem.sampling import field_samples, records, study_samples  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402
from masonrydem.study import settings  # noqa: E402

study = plan.study(sm.config)
g = load_scene(study.scene).geometry
nonspatial, spatial, _ = study_samples(study.samples, study.seed, n_units=g.n_units, n_joints=len(g.joints),
                                       variables=study.variables, correlations=study.correlations)
for variant, path in zip(sm.params.variants, sm.output.samples):
    draw, length = study.variants[variant]["draw"], study.variants[variant]["correlation_length"]
    table = {"wallette": nonspatial, "items": spatial}.get(draw)
    if draw == "field":
        table = field_samples(study.samples, study.seed, study.variables, study.correlations, g.item_centres(), length)
    write_json(path, [{**r, "settings": settings(r, draw, study.variables, study.rules)} for r in records(table)])
    how = {"wallette": "one draw per wallette", "items": "one draw per unit and joint",
           "field": f"random fields, correlation length {length} m"}[draw]
    print(f"{variant}: {len(table)} samples, {how}")
