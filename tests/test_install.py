"""The install's pins (workflow/envs/constraints.txt, which `make install`
passes to pip): every dependency of pyproject.toml, the test tools'
included, pinned to one version inside its range, and this environment
at those versions, so that a fresh clone computes the committed bits."""
import tomllib
from importlib.metadata import version
from pathlib import Path

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
REQUIRED = [Requirement(r) for r in PROJECT["dependencies"] + PROJECT["optional-dependencies"]["test"]]


def _pins():
    lines = [x.strip() for x in (ROOT / "workflow/envs/constraints.txt").read_text().splitlines()]
    pins = {}
    for line in lines:
        if line and not line.startswith("#"):
            name, sep, v = line.partition("==")
            assert sep and v, f"not pinned to one version: {line}"
            pins[canonicalize_name(name)] = v
    return pins


def test_every_dependency_is_pinned_inside_its_range():
    pins = _pins()
    for req in REQUIRED:
        name = canonicalize_name(req.name)
        assert name in pins, f"{req.name} is not pinned in workflow/envs/constraints.txt"
        assert req.specifier.contains(pins[name], prereleases=True), (req, pins[name])


def test_the_makefile_and_the_conda_environment_install_under_the_pins():
    """`make install`, and `--sdm conda`'s environment (its pip runs in
    workflow/envs/ or beside Snakemake's copy of the file, .snakemake/conda/:
    two levels below the root, as the package's own ../.. assumes)."""
    text = (ROOT / "Makefile").read_text()
    assert "CONSTRAINTS := workflow/envs/constraints.txt" in text
    assert "pip install --quiet -e '.[test]' -c $(CONSTRAINTS)" in text
    import yaml
    env = yaml.safe_load((ROOT / "workflow/envs/masonrydem.yaml").read_text())
    pip = next(d["pip"] for d in env["dependencies"] if isinstance(d, dict))
    assert "-e ../.." in pip and "-c ../../workflow/envs/constraints.txt" in pip


def test_this_environment_has_the_pinned_versions():
    pins = _pins()
    wrong = {r.name: (version(r.name), pins[canonicalize_name(r.name)]) for r in REQUIRED
             if version(r.name) != pins[canonicalize_name(r.name)]}
    assert not wrong, f"installed, pinned: {wrong} (make install, or pin what the results were made with)"
