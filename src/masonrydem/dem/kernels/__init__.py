"""Hot kernels: every jitted function of the solver lives in this package.

Modules: ``layout`` (law ids, array columns, the named containers),
``linalg`` (3x3 eigen-decomposition, rotations), ``zones`` (block
material laws and the zone forces), ``cells`` (elastic cells as one
matrix each), ``joint_laws`` (the joint laws), ``joints`` (the
sub-contact forces), ``lanes`` (the cells, sub-contacts and nodes across
the lanes of a batch), ``step`` (the time step and its entry point).

numba's settings and the private parts of it the package relies on (the
SLP vectoriser, the cache locators, the cache's lock): ``jit``.
"""
from . import jit  # noqa: F401  (before any kernel compiles)
from .layout import *  # noqa: F401,F403  (the constants, as kernels.ZP_K etc.)
