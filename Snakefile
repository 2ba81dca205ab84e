# forcenet: every figure and table of P1 and P2 from a config file.
#   snakemake --cores 2                                 # quick default (config/config.yaml)
#   snakemake --cores 2 --configfile config/paper.yaml  # the papers' sizes
# A --configfile stands alone (it is not merged onto config/config.yaml): common.smk reads the default only when
# no --configfile is given, and validates whichever config it is before any job.
from snakemake.utils import min_version

min_version("9.0")


include: "workflow/rules/common.smk"
include: "workflow/rules/setup.smk"
include: "workflow/rules/simulate.smk"
include: "workflow/rules/analyze.smk"
include: "workflow/rules/p2.smk"
include: "workflow/rules/figures.smk"  # after p2.smk: the P2 figures read its states a, b, c
include: "workflow/rules/validation.smk"


rule all:
    input:
        all_targets(),
    default_target: True
