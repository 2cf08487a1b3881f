# Reduced models of the wallette (issue 7):  snakemake --cores 2 reduced
# Each joint-dominated case with rigid units, elastic units and the full
# elasto-plastic model, at the study's numerics: how far P_max moves, how
# much faster it runs.


wildcard_constraints:
    model="|".join(config.get("reduced", {}).get("models", {"none": []})),


rule reduced_run:
    """One case with one model (scene physics overrides)."""
    input:
        scene=config["scene"],
    output:
        result=R + "/reduced/runs/{case}_{model}/result.parquet",
        curve=R + "/reduced/runs/{case}_{model}/curve.parquet",
    params:
        overrides=lambda w: effective(config["numerics"], reduced_cases()[w.case], config["reduced"]["models"][w.model]),
        solver=get_solver_hash(),
    log:
        R + "/logs/reduced/{case}_{model}.log",
    threads: 1
    script:
        "../scripts/run.py"


rule reduced:
    """The table of the reduced models: P_max and run time against the full model."""
    input:
        results=expand(R + "/reduced/runs/{case}_{model}/result.parquet", case=reduced_cases(),
                       model=config["reduced"]["models"] if "reduced" in config else []),
        template=template("reduced"),
    output:
        table=report(R + "/reduced/summary.csv", caption=caption("reduced"), category="Reduced models"),
        caption=caption("reduced"),
    params:
        tolerance=config["reduced"]["tolerance"] if "reduced" in config else None,
    log:
        R + "/logs/reduced/summary.log",
    script:
        "../scripts/reduced.py"
