"""The Willis study, loaded from its study file (config/studies/willis.yaml)
as the tests' fixture: its variables, correlations, terms, columns and
swept level are the file's, never constants of the code."""
import pytest

from masonrydem.analysis.statistics import Level
from masonrydem.dem import lock_kernel_cache
from masonrydem.study.file import load_study

# the test processes of `make test` (pytest-xdist) and the workflow's jobs
# they start share the kernel cache: its entries saved and loaded under a
# lock, as `masonrydem run` does
lock_kernel_cache()

WILLIS_STUDY = "config/studies/willis.yaml"


def willis_study():
    return load_study(WILLIS_STUDY)


@pytest.fixture(scope="session")
def willis():
    """The typed Willis study."""
    return willis_study()


@pytest.fixture(scope="session")
def level(willis):
    """The Willis study's swept level (sigma_v in MPa)."""
    return Level(willis.level_column(), willis.sweep_name, willis.level_unit())


@pytest.fixture(scope="session")
def columns(willis):
    """Input -> its runs-table column (f_tj -> f_tj_mpa)."""
    return willis.columns()


@pytest.fixture(scope="session")
def spec(willis):
    """What the Willis study's analysis needs (pipeline.plan.spec)."""
    from masonrydem.pipeline.plan import spec
    return spec(willis)


@pytest.fixture(scope="session")
def inputs(willis):
    """The random inputs' columns, in the study file's order."""
    return [willis.column(v.name) for v in willis.variables]


def pytest_collection_modifyitems(config, items):
    """The workflow's tests first (a stable sort): they are the suite's
    longest file, and in `make test`'s processes a file started last would
    end alone."""
    items.sort(key=lambda item: item.path.name != "test_workflow.py")
