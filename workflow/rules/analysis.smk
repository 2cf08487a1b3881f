from snakemake.exceptions import WorkflowError

# the study's two long analyses, its equations' and its indices' intervals,
# each on half the cores: they run side by side, first (priority 2, and the
# statistics that the indices wait for), then the pictures (1), the short
# figures and tables in the gaps (a command that runs nothing, such as
# --report, gives no --cores: any number will do)
try:
    ANALYSIS_THREADS = max(1, workflow.cores // 2)
except WorkflowError:
    ANALYSIS_THREADS = 1
FIGURE_CAPTIONS = ["running_mean", "brick_share", "correlation_vs_sigma", "scatter_deviation", "curves_by_mode"]
REGRESSION_CAPTIONS = ["equations", "design_comparison"]


rule figures:
    """Running mean, brick share, correlations, scatter plots, curves by mode."""
    input:
        runs=f"{R}/study/runs.parquet",
        curves=f"{R}/study/curves.parquet",
        statistics=f"{R}/study/statistics.csv",
        correlations=f"{R}/study/correlations.csv",
        templates=[get_template(n) for n in FIGURE_CAPTIONS],
    output:
        running_mean=item(f"{R}/study/running_mean.png", "running_mean", "Study", "Running mean of P_max"),
        brick_share=item(f"{R}/study/brick_share.png", "brick_share", "Study", "Share of brick failures"),
        correlation=item(f"{R}/study/correlation_vs_sigma.png", "correlation_vs_sigma", "Study",
                         "Correlations against precompression"),
        scatter=item(f"{R}/study/scatter_deviation.png", "scatter_deviation", "Study",
                     "P_max against each random input"),
        curves=item(f"{R}/study/curves_by_mode.png", "curves_by_mode", "Study", "Load-displacement curves by mode"),
        captions=[get_caption_file(n) for n in FIGURE_CAPTIONS],
    params:
        code=get_code("figures"),
        analysis=plan.analysis(config),
    log:
        f"{R}/logs/study/figures.log",
    conda:
        ENV
    script:
        "../scripts/figures.py"


rule regression:
    """Lasso prediction equations per mode and the design-rule comparison."""
    input:
        runs=f"{R}/study/runs.parquet",
        scene=get_study_scene(),
        templates=[get_template(n) for n in REGRESSION_CAPTIONS],
    output:
        equations=f"{R}/study/equations.csv",
        predictor=f"{R}/study/predictor.json",
        predicted=item(f"{R}/study/predicted_vs_simulated.png", "equations", "Prediction",
                       "Predicted against simulated strength"),
        design=item(f"{R}/study/design_comparison.png", "design_comparison", "Prediction",
                    "Design rules against the simulations"),
        design_table=f"{R}/study/design_comparison.csv",
        captions=[get_caption_file(n) for n in REGRESSION_CAPTIONS],
    params:
        code=get_code("regression"),
        bootstrap=config["study"]["bootstrap"],
        analysis=plan.analysis(config),
        settings=get_study_settings(),     # for predict: the inputs that change the brick
    log:
        f"{R}/logs/study/regression.log",
    threads: ANALYSIS_THREADS      # the bootstrap's refits on processes (equations.equation_intervals)
    priority: 2
    conda:
        ENV
    script:
        "../scripts/regression.py"


rule sensitivity:
    """Sobol indices of the strength per variant, level and mode, on a
    surrogate of the runs (src/masonrydem/analysis/sensitivity.py)."""
    input:
        runs=f"{R}/study/runs.parquet",
        correlations=f"{R}/study/correlations.csv",
        template=get_template("sensitivity"),
    output:
        table=f"{R}/study/sensitivity.csv",
        figure=item(f"{R}/study/sensitivity.png", "sensitivity", "Study", "Sobol indices"),
        caption=get_caption_file("sensitivity"),
    params:
        code=get_code("sensitivity"),
        analysis=plan.analysis(config),
        draw=get_study_draw(),
        seed=plan.study(config).seed,
    log:
        f"{R}/logs/study/sensitivity.log",
    threads: ANALYSIS_THREADS      # the groups on processes (sensitivity.sensitivity_table)
    priority: 2
    conda:
        ENV
    script:
        "../scripts/sensitivity.py"


rule characteristic:
    """The 5 % fractile of the strength per variant and level, two ways,
    beside the design rules (src/masonrydem/analysis/fractiles.py)."""
    input:
        runs=f"{R}/study/runs.parquet",
        design=f"{R}/study/design_comparison.csv",
        template=get_template("characteristic"),
    output:
        table=f"{R}/study/characteristic.csv",
        caption=get_caption_file("characteristic"),
    params:
        code=get_code("characteristic"),
        analysis=plan.analysis(config),
    log:
        f"{R}/logs/study/characteristic.log",
    conda:
        ENV
    script:
        "../scripts/characteristic.py"


if "paper_comparison" in PAGES:

    rule scorecard:
        """The source paper's published figures beside ours, with our intervals."""
        input:
            runs=f"{R}/study/runs.parquet",
            statistics=f"{R}/study/statistics.csv",
            increase=f"{R}/study/increase.csv",
            equations=f"{R}/study/equations.csv",
            paper=config["study"]["paper"],
            template=get_template("paper_comparison"),
        output:
            table=f"{R}/study/paper_comparison.csv",
            figure=item(f"{R}/study/paper_comparison.png", "paper_comparison", "Paper side by side",
                        "The paper's figures beside ours"),
            caption=get_caption_file("paper_comparison"),
        params:
            code=get_code("scorecard"),
            bootstrap=config["study"]["bootstrap"],
            analysis=plan.analysis(config),
        log:
            f"{R}/logs/study/scorecard.log",
        conda:
            ENV
        script:
            "../scripts/scorecard.py"


# the tables of each stage as pages of the report (common.smk, PAGES): rule
# tables for the study's, tables_STAGE for another stage's
for stage in dict.fromkeys(p[4] for p in PAGES.values()):

    rule:
        name: "tables" if stage == "study" else f"tables_{stage}"
        input:
            **{n: p[0] for n, p in PAGES.items() if p[4] == stage},
        output:
            # labelled by their short names (the navigation's width is its longest label's), titled in full
            **{n: item(f"{R}/report/tables/{n}.html", p[3], p[2], f"{n.replace('_', ' ').capitalize()}: table")
               for n, p in PAGES.items() if p[4] == stage},
        params:
            code=get_code("tables"),
            titles={n: p[1] for n, p in PAGES.items() if p[4] == stage},
        log:
            f"{R}/logs/report/tables_{stage}.log",
        conda:
            ENV
        script:
            "../scripts/tables.py"


rule further_studies:
    """Pages of the report for further studies (config further_studies),
    from the tables their own workflow runs committed."""
    input:
        **{f"{n}_{t}": f"{s['results']}/study/{t}.csv" for n, s in FURTHER.items() for t in ("statistics", "equations")},
        template=get_template("further_study"),
        # each study's figures and pictures, with the captions its own workflow wrote
        figures=[item(path, os.path.abspath(f"{s['results']}/report/{caption}.rst"), "Further studies", label,
                      s["short"]) for s in FURTHER.values() for path, caption, label in get_further_figures(s)],
    output:
        **{f"{n}_page": item(f"{R}/report/studies/{n}.html", f"further_study_{n}", "Further studies",
                             "Statistics and equations", s["short"]) for n, s in FURTHER.items()},
        **{f"{n}_caption": get_caption_file(f"further_study_{n}") for n in FURTHER},
    params:
        studies=FURTHER,
        specs={n: plan.further_study(s["workflow"]) for n, s in FURTHER.items()},
        code=get_code("further_studies"),
    log:
        f"{R}/logs/study/further_studies.log",
    conda:
        ENV
    script:
        "../scripts/further_studies.py"


if config.get("geometry_formats"):

    rule geometry_formats:
        """The geometry study's equations on formats they were not fitted to
        (src/masonrydem/analysis/brick_formats.py)."""
        input:
            predictor=f"{config['geometry_formats']['equations']}/study/predictor.json",
            equations=f"{config['geometry_formats']['equations']}/study/equations.csv",
            fitted=f"{config['geometry_formats']['equations']}/study/runs.parquet",
            runs=[get_format_runs(n) for n in config["geometry_formats"]["formats"]],
            own=f"{R}/study/predictor.json",
            studies=[f["study"] for f in config["geometry_formats"]["formats"].values()],
            template=get_template("geometry_formats"),
        output:
            table=f"{R}/studies/geometry_formats.csv",
            page=item(f"{R}/report/tables/geometry_formats.html", "geometry_formats", "Further studies",
                      "Equations on held-out formats", "brick formats"),
            caption=get_caption_file("geometry_formats"),
        params:
            formats=config["geometry_formats"]["formats"],
            code=get_code("geometry_formats"),
        log:
            f"{R}/logs/study/geometry_formats.log",
        conda:
            ENV
        script:
            "../scripts/geometry_formats.py"
