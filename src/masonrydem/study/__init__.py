"""A stochastic study defined in a file: the file read and checked
against its scene (file.py, study_schema.yaml) into a typed ``Study``
(typed.py), whose ``draw(variant)`` is the one place samples are drawn: Latin
Hypercube samples and random fields (sampling.py), each sample's scene
settings (settings.py), Saltelli's pick-freeze points (copula.py), the
terms of its equations (terms.py).

Nothing here needs the solver: a study reads its scene through
masonrydem.scene, so the samples do not depend on the solver."""
from .file import check_samples, load_study, with_levels
from .sampling import Variable
from .terms import MIN_SAMPLES, parse_term
from .typed import Draw, Study

__all__ = ["MIN_SAMPLES", "Draw", "Study", "Variable", "check_samples", "load_study", "parse_term", "with_levels"]
