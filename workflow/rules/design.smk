# From a lab sheet to a design value (docs/lab-to-design.md): a study whose
# variables were fitted to a lab's results (masonrydem fit), its runs
# re-weighted under the lab's uncertainty.  Only where the workflow config
# has a 'design' section (config/studies/waal_lab_workflow.yaml).


if config.get("design"):

    rule design:
        """The wallette's characteristic flexural strength per level with an
        interval that includes the lab tests' uncertainty, its design value,
        EN 1996-1-1's f_xk2 and AS 3700 beside it."""
        input:
            runs=f"{R}/study/runs.parquet",
            study=config["study"]["file"],
            lab=[r["data"] for r in plan.study(config).provenance.values()],
            template=get_template("design"),
        output:
            table=f"{R}/design/design.csv",
            page=item(f"{R}/report/tables/design.html", "design", "Design value",
                      "Characteristic and design values: table"),
            caption=get_caption_file("design"),
        params:
            code=get_code("design"),
            design=config["design"],
            analysis=plan.analysis(config),
        log:
            f"{R}/logs/design/design.log",
        conda:
            ENV
        script:
            "../scripts/design.py"


if config.get("directions"):

    rule directions:
        """Both bending directions of the study on the same samples: f_x1
        and f_x2 per level with their intervals, mu = f_x1 / f_x2 with
        Fieller's interval, the codes beside them."""
        input:
            runs=f"{R}/study/runs.parquet",
            pair=os.path.normpath(os.path.join(R, config["directions"]["pair"], "study", "runs.parquet")),
            wallettes=[config["directions"]["wallettes"]] if config["directions"].get("wallettes") else [],
            template=get_template("directions"),
        output:
            table=f"{R}/study/directions.csv",
            tests=f"{R}/study/wallette_tests.csv",
            figure=item(f"{R}/study/directions.png", "directions", "Directions", "f_x1, f_x2 and mu per level"),
            page=item(f"{R}/report/tables/directions.html", "directions", "Directions",
                      "f_x1, f_x2, mu and the codes: table"),
            caption=get_caption_file("directions"),
        params:
            code=get_code("directions"),
            directions=config["directions"],
            analysis=plan.analysis(config),
        log:
            f"{R}/logs/study/directions.log",
        conda:
            ENV
        script:
            "../scripts/directions.py"
