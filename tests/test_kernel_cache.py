"""numba's kernel cache shared by processes that fill it at once
(pipeline.kernel_cache.lock, docs/known-problems.md): a constructed race."""
import multiprocessing
import time

from numba.core import caching

from masonrydem.pipeline.kernel_cache import lock as lock_kernel_cache


def _save(folder, key, data, slow):
    lock_kernel_cache()
    cache = caching.IndexDataCacheFile(str(folder), "kernel", ("stamp", 1))
    if slow:      # a wide window between reading the index and writing it back
        read = cache._load_index

        def slow_read():
            index = read()
            time.sleep(0.5)
            return index
        cache._load_index = slow_read
    cache.save(key, data)


def test_two_processes_saving_two_specialisations_keep_both(tmp_path):
    """Two processes save different entries into one cache while each holds
    the index it read for half a second: each entry gets its own data file,
    and each key loads the data saved under it (unlocked, both would choose
    the first free name and one key would load the other's data)."""
    ctx = multiprocessing.get_context("fork")
    procs = [ctx.Process(target=_save, args=(tmp_path, key, f"code of {key}", True)) for key in ("a", "b")]
    for p in procs:
        p.start()
    for p in procs:
        p.join(30)
        assert p.exitcode == 0
    lock_kernel_cache()
    cache = caching.IndexDataCacheFile(str(tmp_path), "kernel", ("stamp", 1))
    assert cache.load("a") == "code of a" and cache.load("b") == "code of b"
    assert len(list(tmp_path.glob("kernel.*.nbc"))) == 2
