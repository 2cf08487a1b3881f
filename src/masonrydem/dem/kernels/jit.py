"""numba, and the private parts of it that this package relies on, in one
module: pyproject.toml pins numba to the range they were read from, and
tests/test_kernel_cache.py fails loudly on a numba that lays them out
otherwise.

- LLVM's SLP vectoriser, which numba leaves off by default, is turned on
  before any kernel compiles: it turns the lanes' 8-tuples into vector
  instructions.  It reorders no arithmetic (IEEE results unchanged).
- numba's on-disk cache keys a compiled function on its own source file
  only, so an edit in another module that it calls would go unnoticed and
  a stale kernel would run (numba's GitHub issues/1833).  The cache
  locators installed here key every function of the kernels package on
  the contents of all of its modules instead: an edit to any of them
  recompiles every kernel.
- ``lock_cache`` makes the cache safe for processes that fill it at once
  (done here, before any kernel compiles or loads).
- ``max_threads`` and ``set_threads``: the threads a run may use.
"""
import fcntl
import hashlib
import os
from pathlib import Path

import numba
from numba.core import caching, config

config.SLP_VECTORIZE = 1

_HERE = Path(__file__).resolve().parent
_STAMP = hashlib.sha256(b"".join(p.name.encode() + p.read_bytes() for p in sorted(_HERE.glob("*.py")))).hexdigest()


class _PackageStamp:
    """A numba cache locator for the kernels package's functions whose
    source stamp is the hash of every module of the package."""

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


def lock_cache():
    """numba's kernel cache made safe for processes that fill it at once (a
    workflow's jobs, the test processes): an entry is saved under an
    exclusive lock of the cache's folder and loaded under a shared one.
    numba adds an entry by reading the index, choosing a free data file
    and writing both back, with nothing held between; two processes that
    save two specialisations of one kernel at once could otherwise map one
    to the other's code, and a load between an entry's index and its data
    could read a stale file (docs/known-problems.md)."""
    cls = caching.IndexDataCacheFile
    if getattr(cls, "_masonrydem_locked", False):
        return

    def locked(method, mode):
        def call(self, *args):
            try:
                os.makedirs(self._cache_path, exist_ok=True)
                f = open(os.path.join(self._cache_path, ".lock"), "a")
            except OSError:                 # numba's own handling of an unwritable cache
                return method(self, *args)
            with f:
                fcntl.flock(f, mode)        # released when the file closes
                return method(self, *args)
        return call
    cls.save = locked(cls.save, fcntl.LOCK_EX)
    cls.load = locked(cls.load, fcntl.LOCK_SH)
    cls._masonrydem_locked = True


lock_cache()


def max_threads():
    """The most threads numba may use here (its NUMBA_NUM_THREADS)."""
    return numba.config.NUMBA_NUM_THREADS


def set_threads(n):
    numba.set_num_threads(n)
