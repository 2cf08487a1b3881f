rule damage_picture:
    """The cracked, deformed final state of one validation run."""
    input:
        state="results/validation/runs/{run}/state.vtm",
        result="results/validation/runs/{run}/result.parquet",
    output:
        report("results/validation/damage_{run}.png", caption="../report/damage_picture.rst",
               category="3-D pictures", subcategory="{run}"),
    log:
        "logs/validation/damage_{run}.log",
    script:
        "../scripts/damage_picture.py"
