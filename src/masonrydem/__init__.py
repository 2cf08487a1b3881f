"""masonrydem: a deformable-block discrete element solver for masonry
micro-models (see ../shared/spec/solver.md)."""
from .errors import InputError
from .laws import Elastic, JointProps, MohrCoulomb
from .model import Model
from .solver import Solver

__version__ = "0.1.0"


def source_hash():
    """Hash of the package's source files: changes whenever the solver does
    (the workflow passes it as a parameter so that solver changes rerun
    simulations)."""
    import hashlib
    from pathlib import Path
    h = hashlib.sha256()
    for p in sorted(Path(__file__).parent.glob("*.py")) + sorted(Path(__file__).parent.glob("*.yaml")):
        h.update(p.name.encode())
        h.update(p.read_bytes())
    return h.hexdigest()[:12]

__all__ = ["Elastic", "InputError", "JointProps", "Model", "MohrCoulomb", "Solver", "__version__", "source_hash"]
