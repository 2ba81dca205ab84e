# The validation campaign: the studies' generated tables with their provenance, written into the tracked folder
# docs/validation/ (docs/validation/README.md). Only a config at the papers' sizes writes them, one that sets
# paper_size_tables: null (config/validation.yaml, config/paper.yaml):
#   snakemake validation_report --configfile config/validation.yaml --cores N
# Every other config reads them instead (the paper-size column of its validation tables, common.smk), so it
# defines no rule that could overwrite them with its small systems' values.
def run_costs(systems):
    """The cost records of every compression run of `systems`."""
    return [paths.run_cost(RESULTS, s, r) for s in systems for r in realizations(s)]


if PAPER_SIZE_TABLES is not None:

    rule validation_report:
        localrule: True
        run:
            raise WorkflowError(
                f"validation_report writes {paths.VALIDATION_DIR}/ from runs at the papers' sizes, but this config reads "
                f"them (paper_size_tables: {PAPER_SIZE_TABLES}): run it with --configfile config/validation.yaml "
                "(or a config that sets paper_size_tables: null)")

else:

    rule validation_report_p1:
        localrule: True
        input:
            md=[paths.p1_validation_table(RESULTS, "md")],  # lists, one per heading, as for P2
            csv=[paths.p1_validation_table(RESULTS, "csv")],
            costs=run_costs(P1_SYSTEMS + P1_COUNTERPARTS),
        output:
            md=paths.campaign_table("p1", "md"),
            csv=paths.campaign_table("p1", "csv"),
        params:
            study="p1",
            systems=P1_SYSTEMS + P1_COUNTERPARTS,
            title="P1 validation: our runs beside the paper",
            headings=["P1 validation table"],
        script:
            "../scripts/validation_report.py"


    # P2's Tables I-III, then the same tables of the table-states reading beside (p2.smk)
    P2_TABLE_HEADINGS = ["Table I", "Table II", "Table III"]

    rule validation_report_p2:
        localrule: True
        input:
            md=[paths.p2_validation_table(RESULTS, "md")] + [paths.p2_table(RESULTS, i, "md") for i in paths.P2_TABLE_NUMBERS]
               + p2_reading_tables("table_states", "md") + p2_reading_tables("essential_drop", "md"),
            csv=[paths.p2_validation_table(RESULTS, "csv")] + [paths.p2_table(RESULTS, i, "csv") for i in paths.P2_TABLE_NUMBERS]
                + p2_reading_tables("table_states", "csv") + p2_reading_tables("essential_drop", "csv"),
            costs=run_costs(P2_SYSTEMS),
        output:
            md=paths.campaign_table("p2", "md"),
            csv=paths.campaign_table("p2", "csv"),
        params:
            study="p2",
            systems=P2_SYSTEMS,
            title="P2 validation: our runs beside the paper",
            headings=["P2 validation table", *P2_TABLE_HEADINGS,
                      *(f"{heading}, {READINGS[key].label}" for key in ("table_states", "essential_drop")
                        if key in READINGS for heading in P2_TABLE_HEADINGS)],
        script:
            "../scripts/validation_report.py"


    rule validation_report:
        localrule: True
        input:
            (rules.validation_report_p1.output if P1_SYSTEMS else []) + (rules.validation_report_p2.output if P2_SYSTEMS else []),
