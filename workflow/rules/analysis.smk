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
        running_mean=report(f"{R}/study/running_mean.png", caption=get_caption("running_mean"), category="Study"),
        brick_share=report(f"{R}/study/brick_share.png", caption=get_caption("brick_share"), category="Study"),
        correlation=report(f"{R}/study/correlation_vs_sigma.png", caption=get_caption("correlation_vs_sigma"),
                           category="Study"),
        scatter=report(f"{R}/study/scatter_deviation.png", caption=get_caption("scatter_deviation"),
                       category="Study"),
        curves=report(f"{R}/study/curves_by_mode.png", caption=get_caption("curves_by_mode"), category="Study"),
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
        equations=report(f"{R}/study/equations.csv", caption=get_caption("equations"), category="Prediction"),
        predictor=f"{R}/study/predictor.json",
        predicted=report(f"{R}/study/predicted_vs_simulated.png", caption=get_caption("equations"),
                         category="Prediction"),
        design=report(f"{R}/study/design_comparison.png", caption=get_caption("design_comparison"),
                      category="Prediction"),
        design_table=report(f"{R}/study/design_comparison.csv", caption=get_caption("design_comparison"),
                            category="Prediction"),
        captions=[get_caption_file(n) for n in REGRESSION_CAPTIONS],
    params:
        code=get_code("regression"),
        bootstrap=config["study"]["bootstrap"],
        analysis=plan.analysis(config),
        settings=get_study_settings(),     # for predict: the inputs that change the brick
    log:
        f"{R}/logs/study/regression.log",
    threads: 2      # the bootstrap's refits on two processes (equations.equation_intervals)
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
        table=report(f"{R}/study/sensitivity.csv", caption=get_caption("sensitivity"), category="Study"),
        figure=report(f"{R}/study/sensitivity.png", caption=get_caption("sensitivity"), category="Study"),
        caption=get_caption_file("sensitivity"),
    params:
        code=get_code("sensitivity"),
        analysis=plan.analysis(config),
        design=get_study_design(),
        seed=plan.study(config).seed,
    log:
        f"{R}/logs/study/sensitivity.log",
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
        table=report(f"{R}/study/characteristic.csv", caption=get_caption("characteristic"), category="Prediction"),
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


if "paper_comparison" in TABLES:

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
            table=report(f"{R}/study/paper_comparison.csv", caption=get_caption("paper_comparison"),
                         category="Paper side by side"),
            figure=report(f"{R}/study/paper_comparison.png", caption=get_caption("paper_comparison"),
                          category="Paper side by side"),
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


rule tables:
    """The key tables of the study as HTML pages of the report."""
    input:
        **{name: f"{R}/study/{name}.csv" for name in TABLES},
    output:
        **{name: report(f"{R}/report/tables/{name}.html", caption=get_caption(caption), category=category)
           for name, (_, category, caption) in TABLES.items()},
    params:
        code=get_code("tables"),
        titles={name: title for name, (title, _, _) in TABLES.items()},
    log:
        f"{R}/logs/study/tables.log",
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
    output:
        **{f"{n}_page": report(f"{R}/report/studies/{n}.html", caption=get_caption(f"further_study_{n}"),
                               category="Further studies", subcategory=s["title"]) for n, s in FURTHER.items()},
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
            table=report(f"{R}/studies/geometry_formats.csv", caption=get_caption("geometry_formats"),
                         category="Further studies"),
            page=report(f"{R}/report/tables/geometry_formats.html", caption=get_caption("geometry_formats"),
                        category="Further studies"),
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
