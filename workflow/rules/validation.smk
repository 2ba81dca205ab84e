# The validation campaign: the studies' generated tables with their provenance, written into the tracked folder
# docs/validation/ (docs/validation/README.md). Meant for config/validation.yaml (the papers' sizes):
#   snakemake validation_report --configfile config/validation.yaml --cores N
VALIDATION_DIR = "docs/validation"


def run_costs(systems):
    return [run_cost_path(s, r) for s in systems for r in REALIZATIONS]


rule validation_report_p1:
    localrule: True
    input:
        md=f"{RESULTS}/tables/p1_validation.md",
        csv=f"{RESULTS}/tables/p1_validation.csv",
        costs=run_costs(P1_SYSTEMS),
    output:
        md=f"{VALIDATION_DIR}/p1.md",
        csv=f"{VALIDATION_DIR}/p1.csv",
    params:
        study="p1",
        systems=P1_SYSTEMS,
        title="P1 validation: our runs beside the paper",
        headings=["P1 validation table"],
    script:
        "../scripts/validation_report.py"


rule validation_report_p2:
    localrule: True
    input:
        md=[f"{RESULTS}/tables/p2_validation.md"] + [f"{RESULTS}/tables/p2_table{i}.md" for i in (1, 2, 3)],
        csv=[f"{RESULTS}/tables/p2_validation.csv"] + [f"{RESULTS}/tables/p2_table{i}.csv" for i in (1, 2, 3)],
        costs=run_costs(P2_SYSTEMS),
    output:
        md=f"{VALIDATION_DIR}/p2.md",
        csv=f"{VALIDATION_DIR}/p2.csv",
    params:
        study="p2",
        systems=P2_SYSTEMS,
        title="P2 validation: our runs beside the paper",
        headings=["P2 validation table", "Table I", "Table II", "Table III"],
    script:
        "../scripts/validation_report.py"


rule validation_report:
    localrule: True
    input:
        (rules.validation_report_p1.output if P1_SYSTEMS else []) + (rules.validation_report_p2.output if P2_SYSTEMS else []),
