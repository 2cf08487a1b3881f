FIGURE_CAPTIONS = ["running_mean", "brick_share", "correlation_vs_sigma", "scatter_deviation", "curves_by_mode"]
REGRESSION_CAPTIONS = ["equations", "design_comparison"]


rule figures:
    """Running mean, brick share, correlations, scatter plots, curves by mode."""
    input:
        runs=R + "/study/runs.parquet",
        curves=R + "/study/curves.parquet",
        statistics=R + "/study/statistics.csv",
        correlations=R + "/study/correlations.csv",
        templates=[template(n) for n in FIGURE_CAPTIONS],
    output:
        running_mean=report(R + "/study/running_mean.png", caption=caption("running_mean"), category="Study"),
        brick_share=report(R + "/study/brick_share.png", caption=caption("brick_share"), category="Study"),
        correlation=report(R + "/study/correlation_vs_sigma.png", caption=caption("correlation_vs_sigma"),
                           category="Study"),
        scatter=report(R + "/study/scatter_deviation.png", caption=caption("scatter_deviation"),
                       category="Study"),
        curves=report(R + "/study/curves_by_mode.png", caption=caption("curves_by_mode"), category="Study"),
        captions=[caption(n) for n in FIGURE_CAPTIONS],
    log:
        R + "/logs/study/figures.log",
    script:
        "../scripts/figures.py"


rule regression:
    """Lasso prediction equations per mode and the design-rule comparison."""
    input:
        runs=R + "/study/runs.parquet",
        scene=config["scene"],
        templates=[template(n) for n in REGRESSION_CAPTIONS],
    output:
        equations=report(R + "/study/equations.csv", caption=caption("equations"), category="Prediction"),
        predicted=report(R + "/study/predicted_vs_simulated.png", caption=caption("equations"),
                         category="Prediction"),
        design=report(R + "/study/design_comparison.png", caption=caption("design_comparison"),
                      category="Prediction"),
        design_table=report(R + "/study/design_comparison.csv", caption=caption("design_comparison"),
                            category="Prediction"),
        captions=[caption(n) for n in REGRESSION_CAPTIONS],
    log:
        R + "/logs/study/regression.log",
    script:
        "../scripts/regression.py"
