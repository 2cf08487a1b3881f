rule damage_picture:
    """The cracked, deformed final state of one validation run."""
    input:
        state=f"{R}/validation/runs/{{run}}/state.vtm",
        result=f"{R}/validation/runs/{{run}}/result.parquet",
    output:
        report(f"{R}/validation/damage_{{run}}.png", caption="../report/damage_picture.rst",
               category="3-D pictures", subcategory="{run}"),
    params:
        code=get_code("damage_picture"),
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
        pictures=[report(f"{R}/study/pictures/{v}_{m}.png", caption=get_caption("study_pictures"),
                         category="3-D pictures", subcategory="study") for v, m in plan.study_pictures(config)],
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
    conda:
        ENV
    script:
        "../scripts/study_pictures.py"
