# Reduced models of the wallette:  snakemake --cores 2 reduced
# Each joint-dominated case with rigid units, elastic units and the full
# elasto-plastic model, at the study's numerics: how far P_max moves, how
# much faster it runs.


wildcard_constraints:
    model="|".join(config.get("reduced", {}).get("models", {"none": []})),


rule reduced_run:
    """One case with one model (scene physics overrides)."""
    input:
        scene=ancient(config["scene"]),  # by its content: params.scene
    output:
        result=f"{R}/reduced/runs/{{case}}_{{model}}/result.parquet",
        curve=f"{R}/reduced/runs/{{case}}_{{model}}/curve.parquet",
    params:
        sets=get_reduced_sets,
        out=get_run_dir,
        solver=get_solver_hash(),
        python=get_python,
        scene=get_file_digest(config["scene"]),
    log:
        f"{R}/logs/reduced/{{case}}_{{model}}.log",
    threads: 1
    conda:
        ENV
    shell:
        RUN


rule reduced:
    """The table of the reduced models: P_max and run time against the full model."""
    input:
        results=get_reduced_results(),
        scene=config["scene"],
        template=get_template("reduced"),
    output:
        table=f"{R}/reduced/summary.csv",
        caption=get_caption_file("reduced"),
    params:
        code=get_code("reduced"),
        simulations=get_runs(get_reduced_sets, [dict(case=c, model=m) for c, m in plan.reduced_runs(config)]),
        runs=plan.reduced_runs(config),
        overrides=[plan.reduced_overrides(config, c, m) for c, m in plan.reduced_runs(config)],
        tolerance=config.get("reduced", {}).get("tolerance"),
    log:
        f"{R}/logs/reduced/summary.log",
    conda:
        ENV
    script:
        "../scripts/reduced.py"
