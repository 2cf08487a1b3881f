rule reference_run:
    output:
        summary="results/reference/sv{sv}.json",
        curve="results/reference/sv{sv}_curve.csv",
    params:
        settings=config["reference"],
        solver=get_solver_hash(),
    log:
        "logs/reference/sv{sv}.log",
    threads: 1
    script:
        "../scripts/reference_run.py"
