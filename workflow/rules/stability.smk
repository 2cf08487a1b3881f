wildcard_constraints:
    hard="[A-Za-z0-9_.]+",


rule hard_case_run:
    """One hard case at the study's numerics."""
    input:
        scene=ancient(config["scene"]),  # by its content: params.scene
    output:
        result=f"{R}/stability/runs/{{hard}}/result.parquet",
        curve=f"{R}/stability/runs/{{hard}}/curve.parquet",
    params:
        sets=get_hard_case_sets,
        out=get_run_dir,
        solver=get_solver_hash(),
        python=get_python,
        scene=get_file_digest(config["scene"]),
    log:
        f"{R}/logs/stability/{{hard}}.log",
    threads: 1
    conda:
        ENV
    shell:
        RUN


rule hard_cases:
    """The hard-cases table of the report."""
    input:
        results=expand(f"{R}/stability/runs/{{hard}}/result.parquet", hard=plan.hard_case_jobs(config)),
        template=get_template("hard_cases"),
    output:
        table=f"{R}/stability/hard_cases.csv",
        caption=get_caption_file("hard_cases"),
    params:
        code=get_code("hard_cases"),
        simulations=get_runs(get_hard_case_sets, [dict(hard=h) for h in plan.hard_case_jobs(config)]),
        runs=list(plan.hard_case_jobs(config)),
        expect=plan.hard_case_expect(config),
    log:
        f"{R}/logs/stability/hard_cases.log",
    conda:
        ENV
    script:
        "../scripts/hard_cases.py"


rule stability:
    """snakemake --cores 2 stability: the hard-cases table alone."""
    input:
        get_stability_outputs(),
