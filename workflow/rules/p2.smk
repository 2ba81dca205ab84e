# P2: distances between persistence diagrams of consecutive states, Tables I–III and the validation of P2's claims
# (P2's figures are made in figures.smk, from forcenet.plotting.registry). Which system is the frictional one
# (μ = 0.5) and which the frictionless one is their catalog role (config/systems.yaml; forcenet.catalog.p2_roles).
from forcenet.catalog import p2_roles
from forcenet.systems import study_rattler_rule

P2_FRICTIONAL, P2_FRICTIONLESS = p2_roles(config, P2_SYSTEMS)


def p2_table_labels():
    """ρ labels of the three nearby snapshots a, b, c around studies.p2.table_rho (P2 Tables I–III)."""
    from forcenet.systems import select_table_snapshots  # pure numpy: no xarray at parse time

    spec = SYSTEMS[P2_FRICTIONAL]
    indices = select_table_snapshots(spec.rho_grid, config["studies"]["p2"].get("table_rho", 0.79))
    return [spec.rho_labels[i] for i in indices]


# which states a, b, c (forcenet.report.p2_tables.TABLE_STATE_RULES): "jammed" (default) or "literal"
P2_TABLE_STATE_RULE = config["studies"].get("p2", {}).get("table_states", "jammed")


def p2_table_candidates(path=snapshot_path, states="abc", rule=P2_TABLE_STATE_RULE):
    """Files of the candidate states of every realization, realization-major, among which p2_table_states picks
    a, b, c and one realization (forcenet.report.p2_tables.TABLE_STATE_CRITERION): under the "literal" `rule` the
    states a, b, c (or those named by `states`), under "jammed" the first P2_JAMMED_WINDOW states at or above
    table_rho (forcenet.pipeline_p2.p2_candidate_indices; which three are a, b, c is known only from their Z, and a
    P2 run record keeps these states); none when the config has no P2 study."""
    if not P2_FRICTIONAL:
        return []
    if rule == "jammed":
        from forcenet.pipeline_p2 import p2_candidate_indices

        spec = SYSTEMS[P2_FRICTIONAL]
        indices = p2_candidate_indices(spec.rho_grid, config["studies"]["p2"].get("table_rho", 0.79), rule)
        labels = [spec.rho_labels[i] for i in indices]
    else:
        labels = [label for letter, label in zip("abc", p2_table_labels()) if letter in states]
    return [path(P2_FRICTIONAL, r, rho) for r in realizations(P2_FRICTIONAL) for rho in labels]


P2_TABLE_STATES = paths.p2_table_states(RESULTS)
# the P2 products read networks made by the P2 study's rattler rule (P2 §III C keeps rattlers)
P2_RATTLER_RULE = study_rattler_rule(config, P2_FRICTIONAL) if P2_FRICTIONAL else None
ESSENTIAL_CONVENTION = config["analysis"]["essential_convention"]
# P2's products of this build and of its readings beside (common.smk): (rule-name suffix, results folder, the rule
# of states a, b, c, where that rule's choice is written, the convention for never-dying classes). The essential
# reading takes the build's states a, b, c and changes the convention; the table-states reading the other way round.
#: the readings beside that change only the convention for never-dying classes (common.smk)
ESSENTIAL_READINGS = [key for key in ("essential", "essential_drop") if key in READINGS]
P2_BUILDS = [("", RESULTS, P2_TABLE_STATE_RULE, P2_TABLE_STATES, ESSENTIAL_CONVENTION)]
P2_BUILDS += [(f"_{key}_reading", READING_RESULTS[key], P2_TABLE_STATE_RULE, P2_TABLE_STATES, READINGS[key].value)
              for key in ESSENTIAL_READINGS]
if "table_states" in READINGS:  # only beside the jammed rule (forcenet.pipeline.readings_beside)
    P2_BUILDS.append(("_table_states_reading", READING_RESULTS["table_states"], READINGS["table_states"].value,
                      paths.p2_table_states(READING_RESULTS["table_states"]), ESSENTIAL_CONVENTION))

# P2's Tables I-III, Figs 1, 3 and claims compare nearby states of a compression: a study with a sequence (SEQUENCES,
# common.smk) makes its distances and their figures, and a validation table that says why it lists no claim
P2_SEQUENCES = [s for s in P2_SYSTEMS if s in SEQUENCES]
if P2_SEQUENCES:
    P2_BUILDS = []
    SKIPPED.append(f"p2_table1, p2_table2, p2_table3: not made: {', '.join(P2_SEQUENCES)} "
                   f"{'is a sequence' if len(P2_SEQUENCES) == 1 else 'are sequences'} at constant ρ, and the tables "
                   "compare three nearby states of a compression")


def p2_runs(wildcards):
    """The summary of every run of one P2 system (kind "p2_run"), in realization order."""
    return [paths.p2_run(RESULTS, wildcards.system, r) for r in realizations(wildcards.system)]


def p2_run_files(systems):
    return [paths.p2_run(RESULTS, s, r) for s in systems for r in realizations(s)]


# What P2's products read from each run (results/{system}/p2_runs/{realization}.nc, forcenet.pipeline_p2.p2_run_summary):
# its distances under every never-dying convention of the build and its readings, Z, never-dying class and diagram
# point counts, made from the run's analyses; a recorded run's comes from its campaign record (simulate.smk).
from forcenet.pipeline_p2 import p2_conventions

for _name in P2_SYSTEMS:

    rule:
        name:
            f"p2_run_{_name}"
        input:
            [analysis_path(_name, "{realization}", rho) for rho in SYSTEMS[_name].rho_labels],
        output:
            paths.p2_run(RESULTS, _name, "{realization}"),
        wildcard_constraints:
            realization=realizations_except(recorded_runs(_name)),
        log:
            paths.run_log(RESULTS, "p2_run", _name, "{realization}"),
        params:
            system=_name,
            conventions=p2_conventions(config),
        resources:
            runtime=60,
            mem_mb=4000,
        script:
            "../scripts/p2_run.py"


rule p2_distances:
    """d_B, d_W1, d_W2 between consecutive snapshots, normal and tangential networks, β0 and β1."""
    input:
        p2_runs,
    output:
        paths.distances(RESULTS, "{system}"),
    log:
        paths.log(RESULTS, "distances", "{system}"),
    params:
        realizations=realization_numbers,
        essential_convention=ESSENTIAL_CONVENTION,
    resources:
        runtime=60,
        mem_mb=4000,
    script:
        "../scripts/p2_distances.py"


for _key in ESSENTIAL_READINGS:

    rule:
        """The distances with the never-dying classes under an essential reading beside (common.smk)."""
        name:
            f"p2_distances_{_key}_reading"
        input:
            p2_runs,
        output:
            paths.distances(READING_RESULTS[_key], "{system}"),
        log:
            paths.log(READING_RESULTS[_key], "distances", "{system}"),
        params:
            realizations=realization_numbers,
            essential_convention=READINGS[_key].value,
        resources:
            runtime=60,
            mem_mb=4000,
        script:
            "../scripts/p2_distances.py"


for _suffix, _results, _state_rule, _states, _convention in P2_BUILDS:
    if _states != P2_TABLE_STATES or not _suffix:

        rule:
            """Which realization's states a, b, c make Tables I–III and Figs 1, 3 (P2 Fig. 1: Z and <F> almost
            identical)."""
            name:
                f"p2_table_states{_suffix}"
            localrule: True
            input:
                p2_table_candidates(analysis_path, rule=_state_rule),
            output:
                _states,
            log:
                paths.log(_results, "tables", "p2_table_states"),
            params:
                rule=_state_rule,
                table_rho=config["studies"].get("p2", {}).get("table_rho", 0.79),
                dimension=SYSTEMS[P2_FRICTIONAL].dimension if P2_FRICTIONAL else 2,
            script:
                "../scripts/p2_table_states.py"

    rule:
        name:
            f"p2_tables{_suffix}"
        localrule: True
        input:
            snapshots=p2_table_candidates(rule=_state_rule),
            states=_states,
        output:
            csv=[paths.p2_table(_results, i, "csv") for i in paths.P2_TABLE_NUMBERS],
            md=[report(paths.p2_table(_results, i, "md"), caption="../report/p2_tables.rst", category="P2",
                       subcategory=REPORT_TABLES) for i in paths.P2_TABLE_NUMBERS] if not _suffix else
               [paths.p2_table(_results, i, "md") for i in paths.P2_TABLE_NUMBERS],
        log:
            paths.log(_results, "tables", "p2_tables"),
        params:
            rattler_rule=P2_RATTLER_RULE,
            essential_convention=_convention,
            judges=JUDGES_DIGEST,  # common.smk: changed table code reruns the tables
        script:
            "../scripts/p2_tables.py"


def p2_reading_tables(key, fmt="csv"):
    """Tables I–III of a reading beside (its key in READINGS; none when the build has no such reading)."""
    if key not in READINGS:
        return []
    return [paths.p2_table(READING_RESULTS[key], i, fmt) for i in paths.P2_TABLE_NUMBERS]


if not P2_SEQUENCES:

    rule p2_validation:
        localrule: True
        input:
            distances=[paths.distances(RESULTS, s) for s in P2_SYSTEMS],
            tables=rules.p2_tables.output.csv,
            runs=p2_run_files(P2_SYSTEMS),  # never-dying class counts, PD1 point counts (IV.C-8)
            states=P2_TABLE_STATES,
            paper_size=paper_size_input("p2"),
            # the readings beside (common.smk), each judged where it changes a claim
            essential_distances=[paths.distances(READING_RESULTS["essential"], s) for s in P2_SYSTEMS],
            essential_tables=p2_reading_tables("essential"),
            essential_drop_distances=[paths.distances(READING_RESULTS["essential_drop"], s) for s in P2_SYSTEMS]
                                     if "essential_drop" in READINGS else [],
            essential_drop_tables=p2_reading_tables("essential_drop"),
            table_states_tables=p2_reading_tables("table_states"),
        output:
            md=report(paths.p2_validation_table(RESULTS, "md"), caption="../report/table.rst", category="P2",
                      subcategory=REPORT_TABLES),
            csv=paths.p2_validation_table(RESULTS, "csv"),
        log:
            paths.log(RESULTS, "tables", "p2_validation"),
        params:
            frictional=P2_FRICTIONAL,
            frictionless=P2_FRICTIONLESS,
            paper_size=paper_size_table("p2"),
            essential_reading=READINGS["essential"].label,
            essential_drop_reading=READINGS["essential_drop"].label if "essential_drop" in READINGS else None,
            table_states_reading=READINGS["table_states"].label if "table_states" in READINGS else None,
            judges=JUDGES_DIGEST,  # common.smk: a changed judge reruns the table
        script:
            "../scripts/p2_validation.py"

else:
    from forcenet.pipeline import sequence_claims_note

    rule p2_validation:
        localrule: True
        output:
            md=report(paths.p2_validation_table(RESULTS, "md"), caption="../report/table.rst", category="P2",
                      subcategory=REPORT_TABLES),
            csv=paths.p2_validation_table(RESULTS, "csv"),
        log:
            paths.log(RESULTS, "tables", "p2_validation"),
        params:
            paper="P2",
            note=sequence_claims_note("P2", P2_SYSTEMS, [getattr(SYSTEMS[s], "coordinate", "rho") for s in P2_SYSTEMS]),
        script:
            "../scripts/no_claims_table.py"
