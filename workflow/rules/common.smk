import masonrydem

R = config["results"]  # root of every output (config/smoke.yaml: .test/results)


def get_solver_hash():
    """Hash of the solver's source: a param of every simulation rule, so that
    a change to src/ reruns the simulations (Snakemake does not track it)."""
    return masonrydem.source_hash()


def get_validation_runs():
    v = config["validation"]
    return [f"{c['name']}_sv{sv}" for c in v["cases"] for sv in v["precompression_mpa"]]


def get_validation_overrides(wildcards):
    """Scene overrides of one validation run: its case's plus the
    precompression."""
    case = {c["name"]: c["overrides"] for c in config["validation"]["cases"]}[wildcards.case]
    overrides = list(case)
    return overrides + [f"loading.precompression.pressure={float(wildcards.sv) * 1e6}"]


def get_validation_outputs():
    v = config["validation"]
    return (
        [R + "/validation/summary.csv", R + "/validation/load_displacement.png",
         R + "/validation/model_numbering.png"]
        + expand(R + "/validation/damage_{run}.png", run=v["pictures"])
    )


def get_study_runs(kind):
    """Every simulation's result (kind 'result') or curve file."""
    s = config["study"]
    suffix = ".parquet" if kind == "result" else "_curve.parquet"
    return expand(R + "/study/runs/{variant}/sv{sv}/s{sample}" + suffix, variant=s["variants"],
                  sv=s["precompression_mpa"], sample=range(s["n_samples"]))


def get_study_outputs():
    return [R + "/study/" + name for name in (
        "statistics.csv", "correlations.csv", "increase.csv", "sampling_check.csv", "running_mean.png", "brick_share.png",
        "correlation_vs_sigma.png", "scatter_deviation.png", "curves_by_mode.png", "equations.csv",
        "predicted_vs_simulated.png", "design_comparison.png")]
