"""masonrydem: a discrete element solver for masonry micro-models
(deformable or rigid blocks, zero-thickness joints, explicit quasi-static
dynamic relaxation); docs/formulation.md describes it."""
from .errors import InputError
from .laws import Elastic, JointProps, MohrCoulomb
from .model import Model
from .solver import Solver

__version__ = "0.1.0"

# modules that do not decide what a simulation computes (the analysis of
# results, figures, the workflow's planning, the command line)
ANALYSIS_ONLY = ("accuracy.py", "analysis.py", "captions.py", "cli.py", "figures.py", "plan.py", "sampling.py",
                 "validation.py")


def simulation_sources():
    """The package's files that decide what a simulation computes: every
    module and data file but those of ANALYSIS_ONLY (a new module counts
    unless it is listed there)."""
    from pathlib import Path
    here = Path(__file__).parent
    return sorted(p.relative_to(here).as_posix() for p in here.rglob("*")
                  if p.suffix in (".py", ".yaml") and p.name not in ANALYSIS_ONLY and "__pycache__" not in p.parts)


def source_hash():
    """Hash of the source files that decide what a simulation computes (the
    workflow passes it as a parameter of every simulation rule, so that a
    solver change reruns them, and a change to the analysis or the figures
    does not)."""
    import hashlib
    from pathlib import Path
    here = Path(__file__).parent
    h = hashlib.sha256()
    for name in simulation_sources():
        h.update(name.encode())
        h.update((here / name).read_bytes())
    return h.hexdigest()[:12]


__all__ = ["Elastic", "InputError", "JointProps", "Model", "MohrCoulomb", "Solver", "__version__", "source_hash"]
