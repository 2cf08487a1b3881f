# What accuracy costs in time (issue 5):  snakemake --cores 2 accuracy


rule accuracy_run:
    """One run of an accuracy case with one numerical setting."""
    input:
        scene=config["scene"],
    output:
        result=R + "/accuracy/runs/{case}/{setting}/result.parquet",
        curve=R + "/accuracy/runs/{case}/{setting}/curve.parquet",
    params:
        overrides=get_accuracy_overrides,
        solver=get_solver_hash(),
    log:
        R + "/logs/accuracy/{case}_{setting}.log",
    threads: 1
    script:
        "../scripts/run.py"


use rule accuracy_run as accuracy_scaling_run with:
    output:
        result=R + "/accuracy/scaling/courses{courses}/result.parquet",
        curve=R + "/accuracy/scaling/courses{courses}/curve.parquet",
    params:
        overrides=lambda w: config["numerics"] + [f"geometry.courses={w.courses}"],
        solver=get_solver_hash(),
    log:
        R + "/logs/accuracy/scaling_courses{courses}.log",


use rule simulate as simulate_fine with:
    output:
        result=R + "/accuracy/subsample/{variant}/sv{sv}/s{sample}.parquet",
        curve=R + "/accuracy/subsample/{variant}/sv{sv}/s{sample}_curve.parquet",
    params:
        overrides=A["subsample"]["fine"] if A else [],      # complete: independent of the defaults
        solver=get_solver_hash(),
    log:
        R + "/logs/accuracy/subsample_{variant}_sv{sv}_s{sample}.log",


rule accuracy_summary:
    """Errors against the converged reference, the Pareto fronts, the knee."""
    input:
        results=get_accuracy_runs("result"),
        templates=[template("accuracy_convergence"), template("accuracy_choice")],
    output:
        runs=report(R + "/accuracy/runs.csv", caption="../report/accuracy_runs.rst", category="Accuracy"),
        convergence=report(R + "/accuracy/convergence.csv", caption=caption("accuracy_convergence"),
                           category="Accuracy"),
        choice=report(R + "/accuracy/choice.csv", caption=caption("accuracy_choice"), category="Accuracy"),
        pareto=report(R + "/accuracy/pareto.png", caption=caption("accuracy_choice"), category="Accuracy"),
        captions=[caption("accuracy_convergence"), caption("accuracy_choice")],
    params:
        accuracy=A,
        baselines=accuracy_oat_baselines(),
        numerics=config["numerics"],
        path=[grid_setting(c, max(A["subcontact_refine"])) for c in path_cells()] if A else [],
    log:
        R + "/logs/accuracy/summary.log",
    script:
        "../scripts/accuracy_summary.py"


rule accuracy_scaling:
    """Run time against the number of units and the cells per edge."""
    input:
        scaling=expand(R + "/accuracy/scaling/courses{courses}/result.parquet",
                       courses=A["scaling_courses"] if A else []),
        runs=R + "/accuracy/runs.csv",
        template=template("accuracy_scaling"),
    output:
        table=report(R + "/accuracy/scaling.csv", caption=caption("accuracy_scaling"), category="Accuracy"),
        figure=report(R + "/accuracy/scaling.png", caption=caption("accuracy_scaling"), category="Accuracy"),
        caption=caption("accuracy_scaling"),
    params:
        settings=[grid_setting(c, min(A["subcontact_refine"])) for c in A["cells"]] if A else [],
    log:
        R + "/logs/accuracy/scaling.log",
    script:
        "../scripts/accuracy_scaling.py"


rule accuracy_subsample:
    """The study's conclusions at default against fine settings."""
    input:
        default=get_subsample_runs("default") if A else [],
        fine=get_subsample_runs("fine") if A else [],
        template=template("accuracy_subsample"),
    output:
        table=report(R + "/accuracy/subsample.csv", caption=caption("accuracy_subsample"), category="Accuracy"),
        figure=report(R + "/accuracy/subsample.png", caption=caption("accuracy_subsample"),
                      category="Accuracy"),
        caption=caption("accuracy_subsample"),
    params:
        fine=A["subsample"]["fine"] if A else [],
        numerics=config["numerics"],
    log:
        R + "/logs/accuracy/subsample.log",
    script:
        "../scripts/accuracy_subsample.py"


rule accuracy:
    """The accuracy study alone."""
    input:
        get_accuracy_outputs(),
