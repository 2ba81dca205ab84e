# The validation campaign: the studies' generated tables with their provenance, written into the tracked folder
# docs/validation/ (docs/validation/README.md). Only a config at the papers' sizes writes them, one that sets
# paper_size_tables: null (config/validation.yaml, config/paper.yaml):
#   snakemake validation_report --configfile config/validation.yaml --cores N
# Every other config reads them instead (the paper-size column of its validation tables, common.smk), so it
# defines no rule that could overwrite them with its small systems' values.
VALIDATION_DIR = "docs/validation"


def run_costs(systems):
    """The cost records (run_cost.json) of every compression run of `systems`."""
    return [run_cost_path(s, r) for s in systems for r in REALIZATIONS]


if PAPER_SIZE_TABLES is not None:

    rule validation_report:
        localrule: True
        run:
            raise WorkflowError(
                f"validation_report writes docs/validation/ from runs at the papers' sizes, but this config reads "
                f"them (paper_size_tables: {PAPER_SIZE_TABLES}): run it with --configfile config/validation.yaml "
                "(or a config that sets paper_size_tables: null)")

else:

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
