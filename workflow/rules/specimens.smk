# Further standard masonry specimens as scenes (issue 7): direct tension
# parallel to the bed joints and the triplet shear test.
#   snakemake --cores 2 specimens


rule specimen_run:
    """One specimen case: its scene with its overrides."""
    input:
        scene=get_specimen_scene,  # by its content: params.scene
    output:
        result=f"{R}/specimens/runs/{{case}}/result.parquet",
        curve=f"{R}/specimens/runs/{{case}}/curve.parquet",
    params:
        sets=get_specimen_sets,
        out=get_run_dir,
        solver=get_solver_hash(),
        python=get_python,
        scene=lambda wildcards: get_file_digest(get_specimen_scene(wildcards)),
    log:
        f"{R}/logs/specimens/{{case}}.log",
    threads: 1
    conda:
        ENV
    shell:
        RUN


rule specimens:
    """The specimens' responses against the closed forms they have."""
    input:
        results=expand(f"{R}/specimens/runs/{{case}}/result.parquet", case=plan.specimen_cases(config)),
        curves=expand(f"{R}/specimens/runs/{{case}}/curve.parquet", case=plan.specimen_cases(config)),
        scenes=[c["scene"] for c in plan.specimen_cases(config).values()],
        template=get_template("specimens"),
    output:
        table=report(f"{R}/specimens/summary.csv", caption=get_caption("specimens"), category="Specimens"),
        figure=report(f"{R}/specimens/response.png", caption=get_caption("specimens"), category="Specimens"),
        caption=get_caption_file("specimens"),
    params:
        code=get_code("specimens"),
        # the runs' settings and their scenes' contents (each case's own scene)
        simulations=get_runs(get_specimen_sets, [dict(case=c) for c in plan.specimen_cases(config)],
                             [get_file_digest(c["scene"]) for c in plan.specimen_cases(config).values()]),
        cases=plan.specimen_cases(config),
    log:
        f"{R}/logs/specimens/summary.log",
    conda:
        ENV
    script:
        "../scripts/specimens.py"
