rule damage_picture:
    """The cracked, deformed final state of one validation run."""
    input:
        state=f"{R}/validation/runs/{{run}}/state.vtm",
        result=f"{R}/validation/runs/{{run}}/result.parquet",
        scene=config["scene"],      # where the rig's supports and loads sit
    output:
        item(f"{R}/validation/damage_{{run}}.png", "../report/damage_picture.rst", "3-D pictures",
             "Damage at the end of {run}", "validation runs"),
    params:
        code=get_code("damage_picture"),
        overrides=lambda w: plan.validation_overrides(config, *w.run.rsplit("_sv", 1)),
    log:
        f"{R}/logs/validation/damage_{{run}}.log",
    conda:
        ENV
    script:
        "../scripts/damage_picture.py"


rule study_pictures:
    """3-D pictures of typical study runs, per variant and failure mode."""
    input:
        runs=f"{R}/study/runs.parquet",
        samples=expand(f"{R}/study/samples_{{variant}}.json", variant=plan.study_variants(config)),
        scene=get_study_scene(),
        template=get_template("study_pictures"),
    output:
        pictures=[item(f"{R}/study/pictures/{v}_{m}.png", "study_pictures", "3-D pictures",
                       f"{v} variant, {m} failure", "study") for v, m in plan.study_pictures(config)],
        caption=get_caption_file("study_pictures"),
    params:
        code=get_code("study_pictures"),
        analysis=plan.analysis(config),
        pictures=plan.study_pictures(config),
        variants=plan.study_variants(config),
        overrides=config["numerics"],
    log:
        f"{R}/logs/study/pictures.log",
    threads: 1
    priority: 1     # after the two long analyses, before the short tables and figures (analysis.smk)
    conda:
        ENV
    script:
        "../scripts/study_pictures.py"
