# Further standard masonry specimens as scenes (issue 7): direct tension
# parallel to the bed joints and the triplet shear test.
#   snakemake --cores 2 specimens


rule specimen_run:
    """One specimen case: its scene with its overrides."""
    input:
        scene=lambda w: specimen_cases()[w.case]["scene"],
    output:
        result=R + "/specimens/runs/{case}/result.parquet",
        curve=R + "/specimens/runs/{case}/curve.parquet",
    params:
        overrides=lambda w: specimen_cases()[w.case]["overrides"],
        solver=get_solver_hash(),
    log:
        R + "/logs/specimens/{case}.log",
    threads: 1
    script:
        "../scripts/run.py"


rule specimens:
    """The specimens' responses against the closed forms they have."""
    input:
        results=expand(R + "/specimens/runs/{case}/result.parquet", case=specimen_cases()),
        curves=expand(R + "/specimens/runs/{case}/curve.parquet", case=specimen_cases()),
        scenes=[c["scene"] for c in specimen_cases().values()],
        template=template("specimens"),
    output:
        table=report(R + "/specimens/summary.csv", caption=caption("specimens"), category="Specimens"),
        figure=report(R + "/specimens/response.png", caption=caption("specimens"), category="Specimens"),
        caption=caption("specimens"),
    params:
        cases=specimen_cases(),
    log:
        R + "/logs/specimens/summary.log",
    script:
        "../scripts/specimens.py"
