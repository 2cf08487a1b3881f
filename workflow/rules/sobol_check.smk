# The study's Sobol indices checked on the solver itself (config
# sobol_check; src/masonrydem/analysis/sobol_check.py): Saltelli's
# pick-freeze design at one level of the study, N (d + 2) runs of the
# study's per-wallette variant, their direct indices beside the study's.
#   snakemake --cores 2 sobol_check   (part of `all`)


if SOBOL:

    rule sobol_check_sample:
        """The check's points (analysis/sobol_check.py, design) as a
        samples file of the study's form."""
        output:
            samples=f"{R}/sobol_check/samples.json",
        params:
            draw=get_study_draw(),
            check={k: SOBOL[k] for k in ("base", "seed")},
            code=get_code("sobol_check_sample"),
        log:
            f"{R}/logs/sobol_check/sample.log",
        conda:
            ENV
        script:
            "../scripts/sobol_check_sample.py"

    for _k, _samples in enumerate(SOBOL_BATCHES):

        rule:
            """A batch of the check's runs."""
            name:
                f"simulate_sobol_{_k}"
            input:
                samples=f"{R}/sobol_check/samples.json",
                scene=ancient(get_study_scene()),  # by its content: params.scene
            output:
                [f"{R}/sobol_check/runs/s{s}/{kind}.json" for s in _samples for kind in ("result", "curve")],
            params:
                sets=get_level_sets(SOBOL["level_dir"]),
                variant=SOBOL["variant"],
                samples=get_batch_samples(_samples),
                lanes=config["batch"]["lanes"],
                out=get_batch_out(f"{R}/sobol_check/runs"),
                solver=get_solver_hash(),
                scene=get_file_digest(get_study_scene()),
                python=get_python,
            log:
                f"{R}/logs/sobol_check/b{_k}.log",
            benchmark:
                f"{R}/sobol_check/benchmarks/b{_k}.tsv"      # its wall time, for the check's cost
            threads: 1
            resources:
                runtime=get_batch_runtime(_samples),
            conda:
                ENV
            shell:
                RUN_BATCH

    rule sobol_check_collect:
        """The check's runs in one table and their batches' cost: what the
        indices read, so that a change of the study's indices reruns the
        comparison alone (the runs are not kept in a clone)."""
        input:
            results=get_sobol_check_runs("result"),
            benchmarks=[f"{R}/sobol_check/benchmarks/b{k}.tsv" for k in range(len(SOBOL_BATCHES))],
        output:
            runs=f"{R}/sobol_check/runs.parquet",
            timing=f"{R}/sobol_check/timing.csv",
        params:
            code=get_code("sobol_check_collect"),
            simulations=get_runs(lambda w: get_level_sets(SOBOL["level_dir"]), [{}], get_study_draw(),
                                 repr({k: SOBOL[k] for k in ("base", "seed")}), scene=get_study_scene()),
            base=SOBOL["base"],
        log:
            f"{R}/logs/sobol_check/collect.log",
        conda:
            ENV
        script:
            "../scripts/sobol_check_collect.py"

    rule sobol_check_indices:
        """The direct indices and their intervals beside the study's."""
        input:
            runs=f"{R}/sobol_check/runs.parquet",
            timing=f"{R}/sobol_check/timing.csv",
            sensitivity=f"{R}/study/sensitivity.csv",
            template=get_template("sobol_check"),
        output:
            table=f"{R}/sobol_check/check.csv",
            caption=get_caption_file("sobol_check"),
        params:
            code=get_code("sobol_check"),
            check=SOBOL,
            analysis=plan.analysis(config),
        log:
            f"{R}/logs/sobol_check/check.log",
        conda:
            ENV
        script:
            "../scripts/sobol_check.py"


rule sobol_check:
    """snakemake --cores 2 sobol_check: the check alone."""
    input:
        get_sobol_check_outputs(),
