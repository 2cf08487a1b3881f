"""Memory of the pure geometric functions of a model's construction.

The runs of a study share their wallette: the same boxes, meshes, face
grids, quadrature points and interpolation weights, built again for every
sample (a third of a run's fixed cost).  The functions that compute them
depend only on their arguments, so a process keeps their answers: keyed
by the arguments' exact bytes, returned read-only (a caller that wrote
into one would raise, not spoil the next build).
"""
import functools

import numpy as np

LIMIT = 200_000     # answers kept per function (then forgotten at once)


def _frozen(x):
    if isinstance(x, np.ndarray):
        x.flags.writeable = False
    elif isinstance(x, tuple):
        for item in x:
            _frozen(item)
    return x


def memoized(key_of):
    """A decorator: the function's answer kept under ``key_of(*args)`` (a
    hashable of the arguments' exact values)."""
    def decorate(f):
        cache = {}

        @functools.wraps(f)
        def remembered(*args):
            key = key_of(*args)
            hit = cache.get(key)
            if hit is None:
                if len(cache) >= LIMIT:
                    cache.clear()
                hit = cache[key] = _frozen(f(*args))
            return hit
        return remembered
    return decorate


def exact(*values):
    """A hashable of numbers and arrays by their exact bytes (and shapes)."""
    return tuple((v.dtype.str, v.shape, v.tobytes()) if isinstance(v, np.ndarray) else
                 exact(*v) if isinstance(v, (tuple, list)) else v for v in values)
