from masonrydem.validation import hard_case_jobs


wildcard_constraints:
    hard="[A-Za-z0-9_.]+",


rule hard_case_run:
    """One hard case (issue 6) at the study's numerics."""
    input:
        scene=config["scene"],
    output:
        result=R + "/stability/runs/{hard}/result.parquet",
        curve=R + "/stability/runs/{hard}/curve.parquet",
    params:
        overrides=lambda wildcards: effective(config["numerics"], hard_case_jobs(config)[wildcards.hard]),
        solver=get_solver_hash(),
    log:
        R + "/logs/stability/{hard}.log",
    threads: 1
    script:
        "../scripts/run.py"


rule hard_cases:
    """The hard-cases table of the report."""
    input:
        results=expand(R + "/stability/runs/{hard}/result.parquet", hard=hard_case_jobs(config)),
        template=template("hard_cases"),
    output:
        table=report(R + "/stability/hard_cases.csv", caption=caption("hard_cases"), category="Stability"),
        caption=caption("hard_cases"),
    log:
        R + "/logs/stability/hard_cases.log",
    script:
        "../scripts/hard_cases.py"


rule stability:
    """snakemake --cores 2 stability: the hard-cases table alone."""
    input:
        get_stability_outputs(),
