STATISTICS_CAPTIONS = ["statistics", "correlations", "increase"]


rule sample:
    """Latin Hypercube samples of both variants (study.md, 5) and the
    achieved correlations."""
    input:
        template=template("sampling_check"),
    output:
        nonspatial=R + "/study/samples_nonspatial.parquet",
        spatial=R + "/study/samples_spatial.parquet",
        check=report(R + "/study/sampling_check.csv", caption=caption("sampling_check"), category="Study"),
        caption=caption("sampling_check"),
    params:
        # only what sampling reads: a change of any other study setting
        # (levels, curve points) must not redraw the samples and so rerun
        # every simulation
        n_samples=config["study"]["n_samples"],
        seed=config["study"]["seed"],
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
        overrides=config["numerics"],
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
    params:
        curve_points=config["study"]["curve_points"],
    log:
        R + "/logs/study/collect.log",
    script:
        "../scripts/collect.py"


rule statistics:
    """Mean, COV and count of P_max per variant, precompression and mode;
    Pearson correlations with the random inputs."""
    input:
        runs=R + "/study/runs.parquet",
        templates=[template(n) for n in STATISTICS_CAPTIONS],
    output:
        statistics=report(R + "/study/statistics.csv", caption=caption("statistics"), category="Study"),
        correlations=report(R + "/study/correlations.csv", caption=caption("correlations"),
                            category="Study"),
        increase=report(R + "/study/increase.csv", caption=caption("increase"), category="Study"),
        captions=[caption(n) for n in STATISTICS_CAPTIONS],
    log:
        R + "/logs/study/statistics.log",
    script:
        "../scripts/statistics.py"


rule study:
    """snakemake --cores 2 study: the stochastic study alone (samples, the
    1000 simulations, analysis, figures, pictures)."""
    input:
        get_study_outputs(),
