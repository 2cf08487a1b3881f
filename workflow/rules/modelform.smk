# The model-form study:  snakemake --cores 2 modelform
# Each modelling assumption of config 'modelform' varied one at a time on
# the mean-property wallette, in joint and brick failure, at three levels:
# how far P_max and the failure mode move (a tornado chart per level and mode).


rule modelform_run:
    """One case at one level with one option of one assumption (or none: the baseline)."""
    input:
        scene=ancient(config["scene"]),  # by its content: params.scene
    output:
        result=f"{R}/modelform/runs/{{case}}/sv{{sv}}/{{option}}/result.parquet",
        curve=f"{R}/modelform/runs/{{case}}/sv{{sv}}/{{option}}/curve.parquet",
    params:
        sets=get_modelform_sets,
        out=get_run_dir,
        solver=get_solver_hash(),
        python=get_python,
        scene=get_file_digest(config["scene"]),
    log:
        f"{R}/logs/modelform/{{case}}_sv{{sv}}_{{option}}.log",
    threads: 1
    conda:
        ENV
    shell:
        RUN


rule modelform_summary:
    """The model-form summary: every option's change of P_max against its baseline."""
    input:
        results=get_modelform_results(),
        template=get_template("modelform"),
    output:
        table=f"{R}/modelform/summary.csv",
        caption=get_caption_file("modelform"),
    params:
        code=get_code("modelform"),
        simulations=get_runs(get_modelform_sets, [dict(case=c, sv=sv, option=o) for c, sv, o in plan.modelform_runs(config)]),
        runs=plan.modelform_runs(config),
        labels=plan.modelform_labels(config) if config.get("modelform") else {},
    log:
        f"{R}/logs/modelform/summary.log",
    conda:
        ENV
    script:
        "../scripts/modelform.py"


rule tornado:
    """The tornado chart, drawn from the summary alone (it can be redrawn
    where the model-form runs are not: a clone)."""
    input:
        table=f"{R}/modelform/summary.csv",
    output:
        figure=item(f"{R}/modelform/tornado.png", "modelform", "Model form", "Change of P_max by modelling option"),
    params:
        code=get_code("tornado"),
        titles={a["name"]: a["title"] for a in (config.get("modelform") or {}).get("assumptions", []) if "title" in a},
    log:
        f"{R}/logs/modelform/tornado.log",
    conda:
        ENV
    script:
        "../scripts/tornado.py"


rule modelform:
    """snakemake --cores 2 modelform: the model-form study alone."""
    input:
        f"{R}/modelform/summary.csv",
        f"{R}/modelform/tornado.png",
        get_pages("modelform"),
