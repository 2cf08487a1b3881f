wildcard_constraints:
    case="[A-Za-z0-9_]+",
    sv="[0-9.]+",
    variant="nonspatial|spatial",
    sample="[0-9]+",


rule validation_run:
    """One deterministic run of the scene."""
    input:
        scene=config["scene"],
    output:
        result=R + "/validation/runs/{case}_sv{sv}/result.parquet",
        curve=R + "/validation/runs/{case}_sv{sv}/curve.parquet",
        state=R + "/validation/runs/{case}_sv{sv}/state.vtm",
    params:
        overrides=get_validation_overrides,
        solver=get_solver_hash(),
    log:
        R + "/logs/validation/{case}_sv{sv}.log",
    threads: 1
    script:
        "../scripts/run.py"


rule validation_summary:
    """Peaks, initial stiffness, rate and mesh sensitivity; the
    load-displacement figure."""
    input:
        results=expand(R + "/validation/runs/{run}/result.parquet", run=get_validation_runs()),
        curves=expand(R + "/validation/runs/{run}/curve.parquet", run=get_validation_runs()),
        template=template("validation_summary"),
    output:
        table=report(R + "/validation/summary.csv", caption=caption("validation_summary"), category="Validation"),
        figure=report(R + "/validation/load_displacement.png", caption=caption("validation_summary"),
                      category="Validation"),
        caption=caption("validation_summary"),
    log:
        R + "/logs/validation/summary.log",
    script:
        "../scripts/validation_summary.py"


rule model_numbering:
    """The model with its units and joints numbered."""
    input:
        scene=config["scene"],
    output:
        report(R + "/validation/model_numbering.png", caption="../report/model_numbering.rst",
               category="3-D pictures"),
    log:
        R + "/logs/validation/model_numbering.log",
    script:
        "../scripts/model_numbering.py"
