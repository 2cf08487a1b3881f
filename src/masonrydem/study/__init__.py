"""A stochastic study defined in a file: the file read and checked
against its scene (file.py, study_schema.yaml), the terms of its
equations (terms.py), Latin Hypercube samples and random fields
(sampling.py), and each sample's scene settings (settings.py).

sampling.py and settings.py need nothing of the solver, so the samples
do not depend on it."""
