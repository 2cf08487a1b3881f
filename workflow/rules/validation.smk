wildcard_constraints:
    case="[A-Za-z0-9_]+",
    sv="[0-9.]+",
    variant="|".join(plan.study_variants(config)),
    sample="[0-9]+",


rule validation_run:
    """One deterministic run of the scene."""
    input:
        scene=ancient(config["scene"]),  # by its content: params.scene
    output:
        result=f"{R}/validation/runs/{{case}}_sv{{sv}}/result.parquet",
        curve=f"{R}/validation/runs/{{case}}_sv{{sv}}/curve.parquet",
        state=f"{R}/validation/runs/{{case}}_sv{{sv}}/state.vtm",
    params:
        sets=get_validation_sets,
        out=get_run_dir,
        solver=get_solver_hash(),
        python=get_python,
        scene=get_file_digest(config["scene"]),
    log:
        f"{R}/logs/validation/{{case}}_sv{{sv}}.log",
    threads: 1
    conda:
        ENV
    shell:
        RUN


rule validation_summary:
    """Peaks, initial stiffness, rate and mesh sensitivity; the
    load-displacement figure."""
    input:
        results=expand(f"{R}/validation/runs/{{run}}/result.parquet", run=plan.validation_runs(config)),
        curves=expand(f"{R}/validation/runs/{{run}}/curve.parquet", run=plan.validation_runs(config)),
        template=get_template("validation_summary"),
    output:
        table=f"{R}/validation/summary.csv",
        figure=item(f"{R}/validation/load_displacement.png", "validation_summary", "Validation",
                    "Load against displacement"),
        caption=get_caption_file("validation_summary"),
    params:
        code=get_code("validation_summary"),
        runs=plan.validation_runs(config),
    log:
        f"{R}/logs/validation/summary.log",
    conda:
        ENV
    script:
        "../scripts/validation_summary.py"


rule model_numbering:
    """The model with its units and joints numbered."""
    input:
        scene=config["scene"],
    output:
        item(f"{R}/validation/model_numbering.png", "../report/model_numbering.rst", "3-D pictures",
             "Units and joints numbered", "the model"),
    params:
        code=get_code("model_numbering"),
    log:
        f"{R}/logs/validation/model_numbering.log",
    conda:
        ENV
    script:
        "../scripts/model_numbering.py"
