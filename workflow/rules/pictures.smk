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
