rule damage_picture:
    """The cracked, deformed final state of one validation run."""
    input:
        state=R + "/validation/runs/{run}/state.vtm",
        result=R + "/validation/runs/{run}/result.parquet",
    output:
        report(R + "/validation/damage_{run}.png", caption="../report/damage_picture.rst",
               category="3-D pictures", subcategory="{run}"),
    log:
        R + "/logs/validation/damage_{run}.log",
    script:
        "../scripts/damage_picture.py"


rule study_pictures:
    """3-D pictures of typical study runs, per variant and failure mode."""
    input:
        runs=R + "/study/runs.parquet",
        samples=expand(R + "/study/samples_{variant}.parquet", variant=config["study"]["variants"]),
        scene=config["scene"],
        template=template("study_pictures"),
    output:
        pictures=[report(R + f"/study/pictures/{v}_{m}.png", caption=caption("study_pictures"),
                         category="3-D pictures", subcategory="study") for v, m in study_pictures()],
        caption=caption("study_pictures"),
    params:
        pictures=study_pictures(),
        variants=config["study"]["variants"],
        overrides=config["numerics"],
    log:
        R + "/logs/study/pictures.log",
    threads: 1
    script:
        "../scripts/study_pictures.py"
