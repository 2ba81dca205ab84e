# One compression run per (system, realization) → one snapshot per ρ of the system's grid.
# A run with a campaign record (config key records_dir, forcenet.campaign) is restored from it by rule
# restore_{system} instead: its snapshots and cost record come back with zero DEM steps (a P2 system's record: the
# run's summary, results/{system}/p2_runs/, and only the states P2's Tables I-III read, p2_kept_labels). The realization wildcard of
# each system is split between the two rules, so a recorded run is never simulated and an unrecorded one never
# restored; a record made under other settings of its system stops the workflow here, by name.
# One rule per system because each system has its own ρ grid (hence its own list of outputs).
# Snapshots are staged with the checkpoint in .partial/ (forcenet.datasets.paths.staging_dir) and published when the
# run completes, so a run killed half-way resumes from its checkpoint and never leaves outputs that look complete.
# A system with `source:` (states from another code or an experiment) is imported instead: rule import_{system}
# writes the same snapshots (forcenet.importers), and everything downstream treats them alike.
from forcenet.campaign import p2_kept_labels, p2_system, realizations_except, recorded_realizations, records_folder
from forcenet.importers import run_files
from forcenet.systems import ImportedSystem


def recorded_runs(name):
    """The realizations of system `name` that its campaign records restore (none without records_dir)."""
    try:
        return recorded_realizations(config, name)
    except ForcenetError as error:
        raise WorkflowError(f"Invalid config: {error}") from None


for _name, _spec in SYSTEMS.items():
    if isinstance(_spec, ImportedSystem):

        rule:
            name:
                f"import_{_name}"
            localrule: True
            input:
                lambda wildcards, name=_name: run_files(config["systems"][name],
                                                        realization_index(wildcards.realization)),
            output:
                snapshots=[snapshot_path(_name, "{realization}", rho) for rho in _spec.rho_labels],
            log:
                paths.run_log(RESULTS, "import", _name, "{realization}"),
            params:
                system=_name,
                depends_on=system_params(_name),
            threads: 1
            script:
                "../scripts/import_states.py"

        continue

    _recorded = recorded_runs(_name)
    _p2 = p2_system(config, _name)
    if _recorded:

        rule:
            name:
                f"restore_{_name}"
            localrule: True
            input:
                # ancient: a record committed (or checked out) after the run was simulated here does not redo it
                ancient((paths.p2_record_file if _p2 else paths.record_file)(records_folder(config), _name,
                                                                             "{realization}")),
            output:
                snapshots=[snapshot_path(_name, "{realization}", rho)
                           for rho in (p2_kept_labels(config, _name) if _p2 else _spec.rho_labels)],
                cost=paths.run_cost(RESULTS, _name, "{realization}"),
                **({"summary": paths.p2_run(RESULTS, _name, "{realization}")} if _p2 else {}),
            wildcard_constraints:
                realization="|".join(_recorded),
            log:
                paths.run_log(RESULTS, "restore", _name, "{realization}"),
            params:
                system=_name,
                depends_on=system_params(_name),
            threads: 1
            script:
                "../scripts/restore_run.py"

    rule:
        name:
            f"simulate_{_name}"
        output:
            snapshots=[snapshot_path(_name, "{realization}", rho) for rho in _spec.rho_labels],
            cost=paths.run_cost(RESULTS, _name, "{realization}"),
        wildcard_constraints:
            realization=realizations_except(_recorded),
        log:
            paths.run_log(RESULTS, "simulate", _name, "{realization}"),
        params:
            system=_name,
            depends_on=system_params(_name),
        threads: 1
        resources:
            runtime=lambda wildcards, attempt, spec=_spec: simulation_runtime_minutes(spec) * attempt,
            mem_mb=lambda wildcards, spec=_spec: simulation_memory_mb(spec),
        script:
            "../scripts/simulate.py"
