"""masonrydem: a deformable-block discrete element solver for masonry
micro-models (see ../shared/spec/solver.md)."""
from .errors import InputError
from .laws import Elastic, JointProps, MohrCoulomb
from .model import Model
from .solver import Solver

__version__ = "0.1.0"


SIMULATION_SOURCES = ("classify.py", "errors.py", "kernels.py", "laws.py", "mesh.py", "model.py", "runner.py",
                      "scene.py", "scene_schema.yaml", "solver.py", "study.py", "viz.py")


def source_hash():
    """Hash of the source files that decide what a simulation computes (the
    workflow passes it as a parameter of every simulation rule, so that a
    solver change reruns them, and a change to the analysis or the figures
    does not)."""
    import hashlib
    from pathlib import Path
    here = Path(__file__).parent
    h = hashlib.sha256()
    for name in SIMULATION_SOURCES:
        h.update(name.encode())
        h.update((here / name).read_bytes())
    return h.hexdigest()[:12]

__all__ = ["Elastic", "InputError", "JointProps", "Model", "MohrCoulomb", "Solver", "__version__", "source_hash"]
