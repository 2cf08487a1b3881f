# masonrydem workflow: `snakemake --cores 2` reproduces every result.
from snakemake.utils import validate


configfile: "config/config.yaml"


validate(config, "config/schema.yaml", set_default=True)


include: "workflow/rules/common.smk"
include: "workflow/rules/reference.smk"


rule all:
    default_target: True
    input:
        get_reference_outputs(),
