# masonrydem workflow: `snakemake --cores 2` reproduces every result.


configfile: "config/config.yaml"


include: "workflow/rules/common.smk"
include: "workflow/rules/validation.smk"
include: "workflow/rules/pictures.smk"
include: "workflow/rules/study.smk"
include: "workflow/rules/analysis.smk"
include: "workflow/rules/accuracy.smk"
include: "workflow/rules/stability.smk"
include: "workflow/rules/reduced.smk"
include: "workflow/rules/specimens.smk"


rule all:
    default_target: True
    input:
        get_validation_outputs(),
        get_study_outputs(),
        get_accuracy_outputs(),
        get_stability_outputs(),
        get_reduced_outputs(),
        get_specimen_outputs(),
