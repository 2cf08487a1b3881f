"""masonrydem: a discrete element solver for masonry micro-models
(deformable or rigid blocks, zero-thickness joints, explicit quasi-static
dynamic relaxation) and stochastic studies of masonry wallettes on it.

The package is in layers, each a folder that imports only from the
layers below it (docs/architecture.md; pyproject.toml states the contract
and `make test` checks it):

    cli        the command line
    pipeline   what a workflow runs: the runs of each stage, checks at planning
    report     captions, figures, pictures
    analysis   statistics, equations, sensitivity, fractiles, predict, validation
    study      a study file: its variables, sampling and samples' settings
    specimen   one wallette test: the scene built into a model, protocol, the result row
    scene      a specimen as plain data: schema, quantities, files, the typed Scene
    dem        the solver: model, laws, assembly, kernels, integration
    errors     bad input;  sources  the version and the solver's source hash

scene and dem are independent of each other (specimen joins them); numba
and the kernels are imported inside dem alone.  What a simulation computes
is decided by ``errors``, ``scene``, ``dem`` and ``specimen`` alone: their
sources make the solver's hash (``sources.source_hash``).  Importing the
package imports nothing else: each layer is imported from its folder
(``from masonrydem.dem import Model``, ``from masonrydem.scene import
build_scene``), and no module of the package imports the package itself.
"""
from .sources import __version__

__all__ = ["__version__"]

