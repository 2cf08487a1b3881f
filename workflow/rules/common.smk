import masonrydem


def get_solver_hash():
    """Hash of the solver's source: a param of every simulation rule, so that
    a change to src/ reruns the simulations (Snakemake does not track it)."""
    return masonrydem.source_hash()


def get_validation_runs():
    v = config["validation"]
    return [f"{case}_sv{sv}" for case in v["cases"] for sv in v["precompression_mpa"]]


def get_validation_overrides(wildcards):
    """Scene overrides of one validation run: its case's plus the
    precompression."""
    overrides = list(config["validation"]["cases"][wildcards.case])
    return overrides + [f"loading.precompression.pressure={float(wildcards.sv) * 1e6}"]


def get_validation_outputs():
    v = config["validation"]
    return (
        ["results/validation/summary.csv", "results/validation/load_displacement.png",
         "results/validation/model_numbering.png"]
        + expand("results/validation/damage_{run}.png", run=v["pictures"])
    )
