rule figures:
    """Running mean, brick share, correlations, scatter plots, curves by mode."""
    input:
        runs=R + "/study/runs.parquet",
        curves=R + "/study/curves.parquet",
        statistics=R + "/study/statistics.csv",
        correlations=R + "/study/correlations.csv",
    output:
        running_mean=report(R + "/study/running_mean.png", caption="../report/running_mean.rst", category="Study"),
        brick_share=report(R + "/study/brick_share.png", caption="../report/brick_share.rst", category="Study"),
        correlation=report(R + "/study/correlation_vs_sigma.png", caption="../report/correlation_vs_sigma.rst",
                           category="Study"),
        scatter=report(R + "/study/scatter_deviation.png", caption="../report/scatter_deviation.rst",
                       category="Study"),
        curves=report(R + "/study/curves_by_mode.png", caption="../report/curves_by_mode.rst", category="Study"),
    log:
        R + "/logs/study/figures.log",
    script:
        "../scripts/figures.py"


rule regression:
    """Lasso prediction equations per mode and the design-rule comparison."""
    input:
        runs=R + "/study/runs.parquet",
    output:
        equations=report(R + "/study/equations.csv", caption="../report/equations.rst", category="Prediction"),
        predicted=report(R + "/study/predicted_vs_simulated.png", caption="../report/predicted_vs_simulated.rst",
                         category="Prediction"),
        design=report(R + "/study/design_comparison.png", caption="../report/design_comparison.rst",
                      category="Prediction"),
        design_table=R + "/study/design_comparison.csv",
    params:
        seed=config["study"]["seed"],
    log:
        R + "/logs/study/regression.log",
    script:
        "../scripts/regression.py"
