"""numba's kernel cache shared by processes that fill it at once."""
import os


def lock():
    """numba's kernel cache made safe for processes that fill it at once (a
    workflow's jobs, the test processes): an entry is saved under an
    exclusive lock of the cache's folder and loaded under a shared one.
    numba adds an entry by reading the index, choosing a free data file
    and writing both back, with nothing held between; two processes that
    save two specialisations of one kernel at once could otherwise map one
    to the other's code, and a load between an entry's index and its data
    could read a stale file (docs/known-problems.md)."""
    import fcntl
    from numba.core import caching

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
