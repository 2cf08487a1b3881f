"""masonrydem: a deformable-block discrete element solver for masonry
micro-models (see ../shared/spec/solver.md)."""
from .errors import InputError
from .laws import Elastic, JointProps, MohrCoulomb
from .model import Model
from .solver import Solver

__version__ = "0.1.0"
__all__ = ["Elastic", "InputError", "JointProps", "Model", "MohrCoulomb", "Solver", "__version__"]
