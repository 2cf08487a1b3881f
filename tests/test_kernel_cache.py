"""numba's kernel cache shared by processes that fill it at once
(dem/kernels/jit.py, lock_cache; docs/known-problems.md): a constructed race."""
import multiprocessing
import time

from numba.core import caching

from masonrydem.dem import lock_kernel_cache


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


def test_every_kernel_is_cached_under_the_stamp_of_the_whole_kernels_package():
    """numba keys a cached kernel on its own file; dem/kernels/__init__.py
    puts its package's locators first in numba's private list of cache
    locators, so that every kernel is keyed on all of the package's
    modules.  numba chooses a kernel's locator as this expects: the
    package's, whose stamp is the hash of the package's files computed
    here again; a function outside the package keeps numba's own.  Fails
    when another numba lays its cache out otherwise (pyproject.toml pins
    the range this was read from)."""
    import hashlib
    from pathlib import Path

    import numba
    from masonrydem.dem import kernels
    from masonrydem.dem.kernels import advance

    folder = Path(advance.__file__).parent
    stamp = hashlib.sha256(b"".join(p.name.encode() + p.read_bytes() for p in sorted(folder.glob("*.py")))).hexdigest()
    impl = caching.CompileResultCacheImpl(advance.advance_nodes.py_func)
    assert type(impl._locator).__name__.startswith("Package"), (numba.__version__, type(impl._locator))
    assert impl._locator.get_source_stamp() == stamp
    outside = caching.CompileResultCacheImpl(_save)
    assert not type(outside._locator).__name__.startswith("Package")
    assert kernels.jit.config.SLP_VECTORIZE == 1


def test_numba_is_in_the_range_whose_private_interface_the_package_reads():
    """The installed numba in pyproject.toml's range, and numba's private
    names the package uses present: a numba outside the range fails here
    loudly, before a stale kernel or an unlocked cache could."""
    import re
    from pathlib import Path

    import numba
    spec = re.search(r'"numba>=([\d.]+),<([\d.]+)"', (Path(__file__).parents[1] / "pyproject.toml").read_text())
    low, high = (tuple(int(x) for x in v.split(".")) for v in spec.groups())
    have = tuple(int(x) for x in numba.__version__.split(".")[:2])
    assert low[:2] <= have < high[:2], f"numba {numba.__version__} is outside {spec.group(0)}"
    for name in ("CacheImpl", "CompileResultCacheImpl", "UserProvidedCacheLocator", "InTreeCacheLocator", "IndexDataCacheFile"):
        assert hasattr(caching, name), f"numba {numba.__version__} has no numba.core.caching.{name}"
    assert isinstance(caching.CacheImpl._locator_classes, list)
    # the private parts (numba's cache internals) are read in one module: dem/kernels/jit.py
    src = Path(__file__).parents[1] / "src" / "masonrydem"
    readers = {p.relative_to(src).as_posix() for p in src.rglob("*.py") if "caching" in p.read_text()}
    assert readers == {"dem/kernels/jit.py"}, readers


def test_an_empty_or_one_row_sub_contact_set_takes_the_kernel_of_a_full_one():
    """contacts.SubContacts.pack and the batches make a sub-contact set's
    2-D arrays Fortran-ordered.  With no row or one they are C-contiguous
    as well, and numba's typeof calls such an array C: a model with no
    bearings would compile a step kernel of its own.  A small wallette's
    step kernel, its bearings replaced by an empty set and by a set of one
    sub-contact (each array as pack makes it), is the same compiled
    function as with its own bearings."""
    import numpy as np

    from masonrydem.dem import init
    from masonrydem.dem.kernels.layout import CONTACTS_FORTRAN
    from masonrydem.dem.kernels.step import specialised
    from masonrydem.scene import build_scene
    from masonrydem.specimen.build import build

    sp = build(build_scene("config/scenes/willis.yaml", [
        "geometry.courses=2", "geometry.units_per_course=2", "numerics.cells=[1, 1, 1]",
        "loading.bending.supports_x=[0.1, 0.5]", "loading.bending.loads_x=[0.25, 0.35]"]))
    args = init(sp.assembly, sp.numerics).batch.args(0)
    full = args[12]
    assert full.area.shape[0] > 1 and full.par.flags.f_contiguous and not full.par.flags.c_contiguous

    def cut(rows):
        return full._replace(**{f: np.asfortranarray(a[:rows]) if f in CONTACTS_FORTRAN else a[:rows]
                                for f, a in full._asdict().items() if a.shape[0] == full.area.shape[0]})
    kernel = specialised(args)
    for rows in (0, 1):
        sc = cut(rows)
        assert sc.par.flags.c_contiguous and sc.par.flags.f_contiguous
        assert specialised(args[:12] + (sc,) + args[13:]) is kernel, rows
