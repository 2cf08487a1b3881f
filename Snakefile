# masonrydem workflow: `snakemake --cores 2` reproduces every result.


configfile: "config/config.yaml"


include: "workflow/rules/common.smk"
include: "workflow/rules/provenance.smk"
include: "workflow/rules/validation.smk"
include: "workflow/rules/pictures.smk"
include: "workflow/rules/study.smk"
include: "workflow/rules/analysis.smk"
include: "workflow/rules/accuracy.smk"
include: "workflow/rules/stability.smk"
include: "workflow/rules/reduced.smk"
include: "workflow/rules/specimens.smk"
include: "workflow/rules/modelform.smk"
include: "workflow/rules/design.smk"
include: "workflow/rules/sobol_check.smk"


# the saved records put back before Snakemake plans, once every rule is
# known; for the report, their run times checked (workflow/rules/provenance.smk)
restore_provenance()
if building_report():
    check_record_times()


# the report's landing page: what was run, how, the key table, where to
# look (written by the rule statistics from workflow/report/workflow.rst)
report: f"{R}/report/workflow.rst"


# The default target: everything but the accuracy study, whose fine
# reference paths take hours (snakemake --cores 2 accuracy); its committed
# summaries (results/accuracy) stand in for it, in the report too
# (snakemake --report results/report.zip all accuracy).
rule all:
    default_target: True
    input:
        get_validation_outputs(),
        get_study_outputs(),
        get_stability_outputs(),
        get_reduced_outputs(),
        get_specimen_outputs(),
        get_further_outputs(),
        get_design_outputs(),
        get_directions_outputs(),
        get_sobol_check_outputs(),


# the records of what made each result, for a clone (workflow/rules/provenance.smk)
onsuccess:
    save_provenance()
