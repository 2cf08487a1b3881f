import hashlib
from pathlib import Path


def get_solver_hash():
    """Hash of the solver's source: a param of every simulation rule, so that
    a change to src/ reruns the simulations (Snakemake does not track it)."""
    h = hashlib.sha256()
    for p in sorted(Path(workflow.basedir, "src", "masonrydem").glob("*.py")):
        h.update(p.read_bytes())
    return h.hexdigest()[:16]


def get_reference_outputs():
    return expand("results/reference/sv{sv}.json", sv=config["reference"]["precompression_mpa"])
