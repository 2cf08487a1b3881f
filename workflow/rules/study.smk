rule sample:
    """Latin Hypercube samples of both variants (study.md, 5) and the
    achieved correlations."""
    output:
        nonspatial=R + "/study/samples_nonspatial.parquet",
        spatial=R + "/study/samples_spatial.parquet",
        check=report(R + "/study/sampling_check.csv", caption="../report/sampling_check.rst",
                     category="Study"),
    params:
        study=config["study"],
    log:
        R + "/logs/study/sample.log",
    script:
        "../scripts/sample.py"


rule simulate:
    """One simulation: a variant, a precompression level, a sample."""
    input:
        samples=R + "/study/samples_{variant}.parquet",
        scene=config["scene"],
    output:
        result=R + "/study/runs/{variant}/sv{sv}/s{sample}.parquet",
        curve=R + "/study/runs/{variant}/sv{sv}/s{sample}_curve.parquet",
    params:
        overrides=config["study"]["scene_overrides"],
        solver=get_solver_hash(),
    log:
        R + "/logs/study/{variant}_sv{sv}_s{sample}.log",
    threads: 1
    script:
        "../scripts/simulate.py"


rule collect:
    """All simulations in one table (failed ones included, with status)."""
    input:
        results=get_study_runs("result"),
        curves=get_study_runs("curve"),
    output:
        runs=R + "/study/runs.parquet",
        curves=R + "/study/curves.parquet",
    log:
        R + "/logs/study/collect.log",
    script:
        "../scripts/collect.py"


rule statistics:
    """Mean, COV and count of P_max per variant, precompression and mode;
    Pearson correlations with the random inputs."""
    input:
        runs=R + "/study/runs.parquet",
    output:
        statistics=report(R + "/study/statistics.csv", caption="../report/statistics.rst", category="Study"),
        correlations=report(R + "/study/correlations.csv", caption="../report/correlations.rst",
                            category="Study"),
        increase=report(R + "/study/increase.csv", caption="../report/increase.rst", category="Study"),
    log:
        R + "/logs/study/statistics.log",
    script:
        "../scripts/statistics.py"
