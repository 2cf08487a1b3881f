STATISTICS_CAPTIONS = ["statistics", "correlations", "increase"]


rule sample:
    """Latin Hypercube samples of both variants (docs/study.md, 7).  Only
    what decides the samples is its params and code: a rerun of this rule
    reruns every simulation (Snakemake plans them before it sees the
    samples unchanged), so their check is a rule of its own."""
    output:
        samples=expand(f"{R}/study/samples_{{variant}}.json", variant=plan.study_variants(config)),
    params:
        # only what sampling reads: a change of any other study setting
        # (levels, curve points) must not redraw the samples
        draw=get_study_draw(),
        variants=plan.study_variants(config),
        code=get_code("sample"),
    log:
        f"{R}/logs/study/sample.log",
    conda:
        ENV
    script:
        "../scripts/sample.py"


rule sampling_check:
    """The samples' achieved correlations and distributions against the
    targets."""
    input:
        template=get_template("sampling_check"),
    output:
        check=f"{R}/study/sampling_check.csv",
        caption=get_caption_file("sampling_check"),
    params:
        draw=get_study_draw(),
        code=get_code("sampling_check"),
    log:
        f"{R}/logs/study/sampling_check.log",
    conda:
        ENV
    script:
        "../scripts/sampling_check.py"


# The simulations, in jobs of config batch.runs (plan.study_batches): a job
# runs its samples of one variant and level in one process, in lock-step
# (RUN_BATCH), and writes each run's row and curve into the run's folder.
for _k, (_variant, _level, _samples) in enumerate(plan.study_batches(config)):

    rule:
        """A batch of the study's simulations: a variant, a level of the
        swept setting, some samples."""
        name:
            f"simulate_{_k}"
        input:
            samples=f"{R}/study/samples_{_variant}.json",
            scene=ancient(get_study_scene()),  # by its content: params.scene
        output:
            [f"{R}/study/runs/{_variant}/{_level}/s{s}/{kind}.json" for s in _samples for kind in ("result", "curve")],
        params:
            sets=get_level_sets(_level),
            variant=_variant,
            samples=get_batch_samples(_samples),
            lanes=config["batch"]["lanes"],
            out=get_batch_out(f"{R}/study/runs/{_variant}/{_level}"),
            solver=get_solver_hash(),
            scene=get_file_digest(get_study_scene()),
            python=get_python,
        log:
            f"{R}/logs/study/{_variant}_{_level}_b{_k}.log",
        threads: 1
        resources:
            runtime=get_batch_runtime(_samples),
        conda:
            ENV
        shell:
            RUN_BATCH


rule collect:
    """All simulations in one table (failed ones included, with status)."""
    input:
        results=get_study_runs("result"),
        curves=get_study_runs("curve"),
    output:
        runs=f"{R}/study/runs.parquet",
        curves=f"{R}/study/curves.parquet",
    params:
        code=get_code("collect"),
        analysis=plan.analysis(config),
        levels=dict(zip(plan.study_level_dirs(config), plan.study_levels(config))),
        simulations=get_study_runs_key(),
        curve_points=config["study"]["curve_points"],
    log:
        f"{R}/logs/study/collect.log",
    conda:
        ENV
    script:
        "../scripts/collect.py"


rule statistics:
    """Mean, COV and count of P_max per variant, precompression and mode;
    Pearson correlations with the random inputs."""
    input:
        runs=f"{R}/study/runs.parquet",
        templates=[get_template(n) for n in STATISTICS_CAPTIONS],
    output:
        statistics=f"{R}/study/statistics.csv",
        correlations=f"{R}/study/correlations.csv",
        increase=f"{R}/study/increase.csv",
        captions=[get_caption_file(n) for n in STATISTICS_CAPTIONS],
    params:
        code=get_code("statistics"),
        bootstrap=config["study"]["bootstrap"],
        analysis=plan.analysis(config),
        report=plan.report_spec(config),
    log:
        f"{R}/logs/study/statistics.log",
    priority: 2     # the sensitivity waits for it (analysis.smk)
    conda:
        ENV
    script:
        "../scripts/statistics.py"


rule landing:
    """The report's landing page: what was run, how, what it found and how
    it compares with the source paper (src/masonrydem/report/landing.py)."""
    input:
        runs=f"{R}/study/runs.parquet",
        statistics=f"{R}/study/statistics.csv",
        card=[f"{R}/study/paper_comparison.csv"] if "paper_comparison" in PAGES else [],
        paper=[config["study"]["paper"]] if config["study"].get("paper") else [],
        template=get_template("workflow"),
    output:
        f"{R}/report/workflow.rst",
    params:
        code=get_code("landing"),
        analysis=plan.analysis(config),
        report=plan.report_spec(config),
        study_file=config["study"]["file"],
    log:
        f"{R}/logs/study/landing.log",
    conda:
        ENV
    script:
        "../scripts/landing.py"


rule study:
    """snakemake --cores 2 study: the stochastic study alone (samples, the
    1000 simulations, analysis, figures, pictures)."""
    input:
        get_study_outputs(),
        get_directions_outputs(),
