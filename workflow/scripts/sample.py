"""Latin Hypercube samples of the study's variants (their check:
sampling_check.py), each record with the scene settings it gives
(study.settings): a job applies them without the study file."""
import sys

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

from masonrydem import plan  # noqa: E402
from masonrydem.results import write_json  # noqa: E402
from masonrydem.sampling import records, study_samples  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402
from masonrydem.study import settings  # noqa: E402

study = plan.study(sm.config)
g = load_scene(study.scene).geometry
nonspatial, spatial, _ = study_samples(study.samples, study.seed, n_units=g.n_units, n_joints=len(g.joints),
                                       variables=study.variables, correlations=study.correlations)
for variant, path in zip(sm.params.variants, sm.output.samples):
    draw = study.variants[variant]
    table = nonspatial if draw == "wallette" else spatial
    write_json(path, [{**r, "settings": settings(r, draw, study.variables, study.rules)} for r in records(table)])
    print(f"{variant}: {len(table)} samples, one draw per {'wallette' if draw == 'wallette' else 'unit and joint'}")
