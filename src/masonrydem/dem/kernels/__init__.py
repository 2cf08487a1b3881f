"""Hot kernels: every jitted function of the solver lives in this package.

Modules: ``layout`` (law ids, array columns, the named containers),
``linalg`` (3x3 eigen-decomposition, rotations), ``zones`` (block
material laws and the zone forces), ``cells`` (elastic cells as one
matrix each), ``joint_laws`` (the joint laws), ``joints`` (the
sub-contact forces), ``lanes`` (the cells, sub-contacts and nodes across
the lanes of a batch), ``step`` (the time step and its entry point).

LLVM's SLP vectoriser, which numba leaves off by default, is turned on
here before any kernel compiles: it turns the lanes' 8-tuples into vector
instructions.  It reorders no arithmetic (IEEE results unchanged).

numba's on-disk cache keys a compiled function on its own source file
only, so an edit in another module that it calls would go unnoticed and a
stale kernel would run (numba's GitHub issues/1833).  The cache locators below key
every function of this package on the contents of all of its modules
instead: an edit to any of them recompiles every kernel.
"""
import hashlib
from pathlib import Path

from numba.core import caching, config

config.SLP_VECTORIZE = 1

from .layout import *  # noqa: F401,F403  (the constants, as kernels.ZP_K etc.)

_HERE = Path(__file__).resolve().parent
_STAMP = hashlib.sha256(b"".join(p.name.encode() + p.read_bytes() for p in sorted(_HERE.glob("*.py")))).hexdigest()


class _PackageStamp:
    """A numba cache locator for this package's functions whose source
    stamp is the hash of every module of the package."""

    def get_source_stamp(self):
        return _STAMP

    @classmethod
    def from_function(cls, py_func, py_file):
        if Path(py_file).resolve().parent != _HERE:
            return None
        return super().from_function(py_func, py_file)


def _install():
    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl          # numba >= 0.60 / older
    bases = [getattr(caching, n, None) or getattr(caching, "_" + n)
             for n in ("UserProvidedCacheLocator", "InTreeCacheLocator")]
    if any(issubclass(c, _PackageStamp) for c in impl._locator_classes):
        return
    impl._locator_classes[:0] = [type(f"Package{b.__name__}", (_PackageStamp, b), {}) for b in bases]


_install()
