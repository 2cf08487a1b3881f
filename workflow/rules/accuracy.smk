# What accuracy costs in time:  snakemake --cores 2 accuracy


rule accuracy_run:
    """One run of an accuracy case with one numerical setting."""
    input:
        scene=ancient(config["scene"]),  # by its content: params.scene
    output:
        result=f"{R}/accuracy/runs/{{case}}/{{setting}}/result.parquet",
        curve=f"{R}/accuracy/runs/{{case}}/{{setting}}/curve.parquet",
    params:
        sets=get_accuracy_sets,
        out=get_run_dir,
        solver=get_solver_hash(),
        python=get_python,
        scene=get_file_digest(config["scene"]),
    log:
        f"{R}/logs/accuracy/{{case}}_{{setting}}.log",
    threads: 1
    conda:
        ENV
    shell:
        RUN


use rule accuracy_run as accuracy_scaling_run with:
    output:
        result=f"{R}/accuracy/scaling/courses{{courses}}/result.parquet",
        curve=f"{R}/accuracy/scaling/courses{{courses}}/curve.parquet",
    params:
        sets=get_scaling_sets,
        out=get_run_dir,
        solver=get_solver_hash(),
        python=get_python,
        scene=get_file_digest(config["scene"]),
    log:
        f"{R}/logs/accuracy/scaling_courses{{courses}}.log",


# the coarsest path level again, apart from the references' own runs: the
# summary's check of the references' table (their runs are not needed for it)
use rule accuracy_run as accuracy_check_run with:
    output:
        result=f"{R}/accuracy/checks/{{case}}/{{setting}}/result.parquet",
        curve=f"{R}/accuracy/checks/{{case}}/{{setting}}/curve.parquet",
    log:
        f"{R}/logs/accuracy/check_{{case}}_{{setting}}.log",


# the accuracy subsample's runs at fine settings, in jobs as the study's
for _k, (_variant, _sv, _samples) in enumerate(plan.subsample_batches(config)):

    rule:
        """A batch of the accuracy subsample's study runs at fine settings."""
        name:
            f"simulate_fine_{_k}"
        input:
            samples=f"{R}/study/samples_{_variant}.json",
            scene=ancient(get_study_scene()),
        output:
            [f"{R}/accuracy/subsample/{_variant}/sv{_sv}/s{s}/{kind}.json" for s in _samples
             for kind in ("result", "curve")],
        params:
            sets=get_fine_sets(SimpleNamespace(sv=_sv)),  # complete: independent of the defaults
            variant=_variant,
            samples=get_batch_samples(_samples),
            lanes=config["batch"]["lanes"],
            out=get_batch_out(f"{R}/accuracy/subsample/{_variant}/sv{_sv}"),
            solver=get_solver_hash(),
            scene=get_file_digest(get_study_scene()),
            python=get_python,
        log:
            f"{R}/logs/accuracy/subsample_{_variant}_sv{_sv}_b{_k}.log",
        threads: 1
        resources:
            runtime=get_batch_runtime(_samples),
            mem_mb=2000,
        conda:
            ENV
        shell:
            RUN_BATCH


rule accuracy_references:
    """The references (the refinement paths, hours of runs) in a table of
    their own, which the summary reads: moving the defaults reruns the
    defaults' runs, not these (snakemake --forcerun accuracy_references)."""
    input:
        results=get_accuracy_results(reference_runs(config)),
    output:
        table=f"{R}/accuracy/references.csv",
    params:
        code=get_code("accuracy_references"),
        simulations=get_runs(get_accuracy_sets, [dict(case=c, setting=s) for c, s in reference_runs(config)]),
        runs=reference_runs(config),
    log:
        f"{R}/logs/accuracy/references.log",
    conda:
        ENV
    script:
        "../scripts/accuracy_references.py"


rule accuracy_summary:
    """Errors against the converged reference, the Pareto fronts, the knee."""
    input:
        results=get_accuracy_results(get_summary_runs()),
        checks=[f"{R}/accuracy/checks/{case}/{setting}/result.parquet" for case, setting in reference_checks(config)],
        references=f"{R}/accuracy/references.csv",
        templates=[get_template("accuracy_convergence"), get_template("accuracy_choice")],
    output:
        runs=f"{R}/accuracy/runs.csv",
        convergence=f"{R}/accuracy/convergence.csv",
        choice=f"{R}/accuracy/choice.csv",
        captions=[get_caption_file("accuracy_convergence"), get_caption_file("accuracy_choice")],
    params:
        code=get_code("accuracy_summary"),
        simulations=get_runs(get_accuracy_sets, [dict(case=c, setting=s) for c, s in
                                                 get_summary_runs() + reference_checks(config)]),
        runs=get_summary_runs(),
        checks=reference_checks(config),
        references=reference_runs(config),
        all_runs=plan.accuracy_runs(config),
        cases=plan.accuracy_cases(config),
        tolerance=config.get("accuracy", {}).get("tolerance"),
        baselines=plan.accuracy_baselines(config),
        numerics=config["numerics"],
        path=plan.path_settings(config),
        candidates=plan.candidate_settings(config),
        path_tolerance=config.get("accuracy", {}).get("path_tolerance"),
    log:
        f"{R}/logs/accuracy/summary.log",
    conda:
        ENV
    script:
        "../scripts/accuracy_summary.py"


rule accuracy_scaling:
    """Run time against the number of units and the cells per edge."""
    input:
        scaling=expand(f"{R}/accuracy/scaling/courses{{courses}}/result.parquet", courses=plan.scaling_courses(config)),
        runs=f"{R}/accuracy/runs.csv",
        template=get_template("accuracy_scaling"),
    output:
        table=f"{R}/accuracy/scaling.csv",
        caption=get_caption_file("accuracy_scaling"),
    params:
        code=get_code("accuracy_scaling"),
        simulations=get_runs(get_scaling_sets, [dict(courses=c) for c in plan.scaling_courses(config)]),
        courses=plan.scaling_courses(config),
        settings=plan.scaling_settings(config),
    log:
        f"{R}/logs/accuracy/scaling.log",
    conda:
        ENV
    script:
        "../scripts/accuracy_scaling.py"


rule accuracy_figures:
    """The accuracy study's figures, drawn from its tables alone: they can be
    redrawn where the accuracy runs are not (a clone)."""
    input:
        runs=f"{R}/accuracy/runs.csv",
        convergence=f"{R}/accuracy/convergence.csv",
        choice=f"{R}/accuracy/choice.csv",
        scaling=f"{R}/accuracy/scaling.csv",
    output:
        pareto=item(f"{R}/accuracy/pareto.png", "accuracy_choice", "Accuracy", "Error against run time"),
        scaling=item(f"{R}/accuracy/scaling.png", "accuracy_scaling", "Accuracy", "Run time against wallette size"),
    params:
        code=get_code("accuracy_figures"),
        tolerance=config.get("accuracy", {}).get("tolerance"),
    log:
        f"{R}/logs/accuracy/figures.log",
    conda:
        ENV
    script:
        "../scripts/accuracy_figures.py"


rule accuracy_subsample:
    """The study's conclusions at default against fine settings."""
    input:
        default=lambda wildcards: get_subsample_runs("default"),   # when planned: the study's runs
        fine=get_subsample_runs("fine"),
        template=get_template("accuracy_subsample"),
    output:
        table=f"{R}/accuracy/subsample.csv",
        figure=item(f"{R}/accuracy/subsample.png", "accuracy_subsample", "Accuracy",
                    "Study samples at the default and fine settings"),
        caption=get_caption_file("accuracy_subsample"),
    params:
        code=get_code("accuracy_subsample"),
        simulations=get_runs(get_fine_sets, [dict(sv=sv) for sv in config.get("accuracy", {}).get("subsample", {}).get("precompression_mpa", [])],
                             get_study_runs_key()),
        fine=plan.subsample_fine(config),
    log:
        f"{R}/logs/accuracy/subsample.log",
    conda:
        ENV
    script:
        "../scripts/accuracy_subsample.py"


rule accuracy:
    """The accuracy study alone."""
    input:
        get_accuracy_outputs(),
