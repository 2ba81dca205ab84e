#!/usr/bin/env python
"""The measured-figures tables of docs/performance.md, made from the benchmarks' latest records (bench/results/).

usage: python bench/report.py [--check] [--page docs/performance.md] [--results bench/results]

Each table sits between ``<!-- bench:NAME -->`` and ``<!-- /bench:NAME -->`` in the page; everything between the two
markers is rewritten from the records, everything outside them (the prose on methods) is left as it is. Below each
table one line per record names its file, date, machine, load, commit and command. A benchmark whose record says
"not measured" (LAMMPS cannot be installed, no build's results) or that has no record yet gets a row that says so.
With --check nothing is written and the exit status is 1 when the page differs from what the records make
(tests/test_bench_records.py checks the same).
"""
from __future__ import annotations

import argparse
import difflib
import re
import sys
from pathlib import Path

import records  # bench/records.py

PAGE = records.REPO / "docs" / "performance.md"
MARKER = re.compile(r"(<!-- bench:(?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- /bench:(?P=name) -->)", re.S)
SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
SAME_STATE_CASES = ("2d_linear", "2d_hertz", "3d_linear", "3d_hertz")
DEM_CASES = ("2d", "3d")


# --- number formats -------------------------------------------------------------------------------------------
def sci(value: float, digits: int = 3) -> str:
    """`digits` significant digits, powers of ten written out below 0.001 and from 1000: 1.57·10⁷, 8.0·10⁻¹⁵,
    0.470, 25.3."""
    if value == 0:
        return "0"
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    exponent = int(exponent)
    if -3 < exponent < 3:
        return f"{value:.{max(digits - 1 - exponent, 0)}f}"
    return f"{mantissa}·10{str(exponent).translate(SUPERSCRIPT)}"


def fixed(value: float, digits: int = 3) -> str:
    """`digits` significant digits without an exponent (≥ 1: at most `digits` - 1 decimals)."""
    if value == 0:
        return "0"
    decimals = max(digits - 1 - int(f"{abs(value):e}".split("e")[1]), 0)
    return f"{value:.{decimals}f}"


def seconds(value: float) -> str:
    return f"{fixed(value, 2)} s" if value < 60 else f"{int(value // 60)} min {round(value % 60):d} s"


def percent(ratio: float) -> str:
    return f"{100 * ratio:.2g} %"


# --- provenance -----------------------------------------------------------------------------------------------
def provenance(items: list[tuple[str, dict]]) -> list[str]:
    """One line per group of records from the same command, day, commit and machine (load: lowest before to
    highest after)."""
    groups: dict[tuple, list[tuple[str, dict]]] = {}
    for stem, record in items:
        machine = record.get("machine", {})
        key = (record.get("command"), record.get("date", "")[:10], record.get("commit"), record.get("dirty"),
               machine.get("cpu"), machine.get("cores"), tuple(machine.get("affinity") or ()))
        groups.setdefault(key, []).append((stem, record))
    lines = []
    for (command, day, commit, dirty, cpu, cores, affinity), group in groups.items():
        files = ", ".join(f"`{stem}.json`" for stem, _ in group)
        pinned = (f", run on CPU {','.join(map(str, affinity))}" if affinity and cores and len(affinity) < cores
                  else "")
        before = [r["machine"]["load_before"][0] for _, r in group if r["machine"].get("load_before")]
        after = [r["machine"]["load_after"][0] for _, r in group if r["machine"].get("load_after")]
        load = f", load average {min(before):.1f} → {max(after):.1f}" if before and after else ""
        tree = f"commit {commit[:10]}{' with uncommitted changes' if dirty else ''}" if commit else "no git commit"
        lines.append(f"<sub>Record {files}: {day}, {cpu}, {cores} cores{pinned}{load}; {tree}; "
                     f"`{command}`.</sub>")
    return lines


def not_measured(record: dict | None, how: str) -> str:
    if record is None:
        return f"no record yet (`{how}`)"
    return f"not measured on this machine: {record.get('reason') or 'no reason recorded'}"


def measured(record: dict | None) -> bool:
    return record is not None and record.get("status") == "measured"


def table(header: list[str], rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header),
            *("| " + " | ".join(row) + " |" for row in rows)]


def lines_with_provenance(body: list[str], used: list[tuple[str, dict]]) -> str:
    return "\n".join([*body, *(line for p in provenance(used) for line in ("", p))]) + "\n"


# --- the tables -----------------------------------------------------------------------------------------------
def same_state_table(recs: dict) -> str:
    rows, used, classic_rows, classic_used = [], [], [], []
    for case in SAME_STATE_CASES:
        dim, law = case.split("_")
        label = f"{dim.upper()} {'Hertz' if law == 'hertz' else law}"
        record = recs.get(f"lammps_same_state-{case}")
        if not measured(record):
            missing = not_measured(record, "bench/lammps_same_state.py")
            rows.append([label, "–", "–", "–", "–", missing, "", "", ""])
        else:
            used.append((f"lammps_same_state-{case}", record))
            for probe, r in record["measured"]["probes"].items():
                rows.append([label, probe, str(r["N"]), str(r["steps"]), str(r["capped"]), sci(r["force"], 2),
                             sci(r["torque_lever_r"], 2), sci(r["torque"], 2), "yes" if r["passed"] else "**no**"])
        classic = recs.get(f"lammps_same_state-{case}-classic_walls")
        if measured(classic):
            classic_used.append((f"lammps_same_state-{case}-classic_walls", classic))
            for probe, r in classic["measured"]["probes"].items():
                classic_rows.append([label, probe, sci(r["force"], 3), sci(r["torque_lever_r"], 3)])
    body = table(["case", "probe", "N", "spring increments", "contacts at the Coulomb cap", "force",
                  "torque, lever r_i", "torque as computed", "round-off (≤ 10⁻⁹)"], rows)
    if classic_rows:
        body += ["", "With LAMMPS's classic wall styles (`--classic-walls`), largest relative difference:", "",
                 *table(["case", "probe", "force", "torque, lever r_i"], classic_rows)]
    return lines_with_provenance(body, used + classic_used)


def dem_vs_lammps_table(recs: dict) -> str:
    rows, used = [], []
    for case in DEM_CASES:
        record = recs.get(f"dem_vs_lammps-{case}")
        if not measured(record):
            label = f"{case.upper()} Hertz"
            rows.append([label, not_measured(record, "bench/dem_vs_lammps.py"), "", "", ""])
            continue
        used.append((f"dem_vs_lammps-{case}", record))
        spec, ours, peer = record["settings"]["case"], record["measured"], record["peer"]["figures"]
        phi_end = ours["runs"][-1]["phi_end"]
        runs = ", ".join(f"{r:.2f}" for r in ours["ratio_runs"])
        rows.append([f"{spec['dim']}D Hertz, N = {ours['runs'][-1]['N']}, φ {spec['phi']:.2f} → {phi_end:.3f}",
                     sci(ours["particle_steps_per_cpu_s"]), sci(peer["particle_steps_per_cpu_s"]),
                     f"**{ours['ratio']:.2f}** (runs: {runs})",
                     f"{ours['contacts_per_particle_end']:.3f} / {peer['contacts_per_particle_end']:.3f}"])
    header = ["state", "ours (particle-steps per CPU-s)", "LAMMPS", "ours / LAMMPS",
              "contacts/particle at the end (ours / LAMMPS)"]
    lammps = {r["peer"].get("version") for _, r in used if r.get("peer")}
    note = [f"LAMMPS {', '.join(sorted(v for v in lammps if v))}, walls `--walls "
            f"{used[0][1]['settings']['walls']}`; medians over {used[0][1]['settings']['repeat']} alternating runs.",
            ""] if used else []
    return lines_with_provenance(note + table(header, rows), used)


def dem_scaling_table(recs: dict) -> str:
    body, used = [], []
    for dim in ("2d", "3d"):
        record = recs.get(f"dem_scaling-{dim}")
        if body:
            body.append("")
        if not measured(record):
            body += table([f"N ({dim.upper()})"], [[not_measured(record, f"bench/dem_scaling.py --dim {dim[0]}")]])
            continue
        used.append((f"dem_scaling-{dim}", record))
        sizes, settings = record["measured"]["sizes"], record["settings"]
        law = "linear" if settings.get("system") == "2d_linear" else "Hertz"
        low, high = (f"{f(s['rho'] for s in sizes):.2f}" for f in (min, max))
        rho = low if low == high else f"{low}–{high}"
        body += table([f"N ({dim.upper()} {law}, ρ {rho}, {settings['steps']} steps)",
                       *(str(s["N"]) for s in sizes)],
                      [["particle-steps per CPU-s", *(sci(s["particle_steps_per_cpu_s"]) for s in sizes)],
                       ["contacts per particle", *(f"{s['contacts_per_particle']:.2f}" for s in sizes)]])
    return lines_with_provenance(body, used)


def dem_profile_table(recs: dict) -> str:
    body, used = [], []
    for case in ("2d", "3d"):
        record = recs.get(f"dem_profile-{case}")
        if body:
            body.append("")
        if not measured(record):
            body += table([f"part of a {case.upper()} step"],
                          [[not_measured(record, f"bench/dem_profile.py --only {case}")]])
            continue
        used.append((f"dem_profile-{case}", record))
        m = record["measured"]
        rows = [[part, f"{1e6 * value:.1f}", percent(m["shares"][part])] for part, value in m["parts_cpu_s"].items()]
        rows.append(["whole step", f"{1e6 * m['whole_step_cpu_s']:.1f}", "100 %"])
        body += table([f"part of a {case.upper()} step (N = {m['N']}, {m['pairs']} listed pairs, {m['rebuilds']} "
                       f"rebuilds in {m['steps']} steps)", "µs per step (CPU)", "share"], rows)
    return lines_with_provenance(body, used)


def dem_profile_record_table(recs: dict) -> str:
    """bench/dem_profile.py --record: the parts of a step on states of a campaign record, one column per state."""
    used = measured_records(recs, lambda stem: stem.startswith("dem_profile-") and stem not in (
        "dem_profile-2d", "dem_profile-3d"), "bench/dem_profile.py --record 3d_hertz/r00")
    if isinstance(used, str):
        return used
    body = []
    for stem, record in used:
        states = record["measured"]
        first = next(iter(states.values()))
        header = [f"part of a step of {record['settings']['record']} (N = {first['N']})",
                  *(f"ρ = {rho}, Z = {m['Z']:.2f}: µs (share)" for rho, m in states.items())]
        rows = [[part, *(f"{1e6 * m['parts_cpu_s'][part]:.1f} ({percent(m['shares'][part])})" for m in states.values())]
                for part in first["parts_cpu_s"]]
        rows.append(["whole step", *(f"{1e6 * m['whole_step_cpu_s']:.1f}" for m in states.values())])
        rows.append(["listed pairs; rebuilds in the timed steps",
                     *(f"{m['pairs']}; {m['rebuilds']} in {m['steps']}" for m in states.values())])
        body += ([""] if body else []) + table(header, rows)
    return lines_with_provenance(body, used)


def analysis_table(recs: dict) -> str:
    record = recs.get("analysis")
    if not measured(record):
        return lines_with_provenance(table(["", "measured", "target"],
                                           [["analysis", not_measured(record, "bench/analysis.py"), ""]]), [])
    m, targets = record["measured"], record["settings"].get("targets_ms", {})

    def target(key: str) -> str:
        return f"≤ {targets[key]:.0f} ms" if key in targets else "–"

    rows = []
    for dim in ("2d", "3d"):
        net = m["networks"][dim]
        rows.append([f"{dim.upper()}, N = {net['N']}, {net['contacts']} contacts",
                     f"{fixed(m[f'snapshot_ms_{dim}'])} ms", target(f"snapshot_ms_{dim}")])
    rows.append(["distances between two consecutive 2D diagrams (PD0 + PD1, d_B, d_W1, d_W2)",
                 f"{fixed(m['distances_ms_2d'])} ms", target("distances_ms_2d")])
    if "distances_ms_2d_small_change" in m:
        rows.append(["the same for a gentler step (forces 1 %, 0.5 % of contacts opened)",
                     f"{fixed(m['distances_ms_2d_small_change'])} ms", "–"])
    return lines_with_provenance(table(["", "measured", "target"], rows), [("analysis", record)])


def p1_table_table(recs: dict) -> str:
    record = recs.get("p1_table")
    header = ["input", "one pass (no resamples)", "one bootstrap resample", "pass + the job's resamples"]
    if not measured(record):
        return lines_with_provenance(table(header, [[not_measured(record, "bench/p1_table.py"), "", "", ""]]), [])
    m = record["measured"]
    systems = m["input"]["systems"]
    shapes = sorted({(s["realizations"], s["rho_points"]) for s in systems.values()})
    shape = "; ".join(f"{r} realization{'s' if r != 1 else ''} × {p} ρ" for r, p in shapes)
    source = ", ".join(m["input"]["config"])
    if m.get("resample_s") is None:
        resample = estimate = "– (one realization per system: nothing to resample)"
    else:
        resample = seconds(m["resample_s"])
        estimate = f"{seconds(m['job_estimate_s'])} ({record['settings'].get('job_resamples', '?')} resamples)"
    return lines_with_provenance(table(header, [[
        f"{source}: {', '.join(systems)} ({shape} each)", seconds(m["pass_s"]), resample, estimate]]),
        [("p1_table", record)])


def workflow_table(recs: dict) -> str:
    record = recs.get("workflow_overhead")
    header = ["what", "measured", "target"]
    if not measured(record):
        return lines_with_provenance(table(header, [["workflow overhead",
                                                     not_measured(record, "bench/workflow_overhead.py"), ""]]), [])
    m, targets = record["measured"], record["settings"].get("targets", {})
    ratio_target = f"≤ {percent(targets['overhead_ratio'])}" if "overhead_ratio" in targets else ""
    rows = []
    for profile in ("default", "slurm"):
        if f"dry_run_s_{profile}" in m:
            rows.append([f"paper config dry-run ({m.get('paper_jobs')} jobs), {profile.replace('slurm', 'Slurm')} "
                         "profile",
                         seconds(m[f"dry_run_s_{profile}"]),
                         f"≤ {seconds(targets['dry_run_s'])}" if "dry_run_s" in targets else ""])
    rows.append(["simulation job overhead (start, imports, bookkeeping, writing) against the kernel, paper 2D",
                 f"{seconds(m['simulation_overhead_s'])} per run against "
                 f"{seconds(m['paper_simulation_kernel_per_snapshot_s'])} of kernel per snapshot: "
                 f"{percent(m['simulation_overhead_ratio_paper'])}", ratio_target])
    rows.append([f"analysis, paper-size 2D snapshot (N = {m['particles']}, {m['contacts']} contacts): kernels / read "
                 f"+ write / job wall per snapshot, local",
                 f"{seconds(m['analysis_kernels_s'])} / {seconds(m['analysis_read_s'] + m['analysis_write_s'])} / "
                 f"{seconds(m['analysis_job_wall_local_s'])}", ""])
    for where in ("local", "slurm"):
        ratios = m.get(f"snapshot_overhead_ratio_{where}")
        label = ("per-snapshot overhead ÷ kernels (simulation + analysis), paper config, "
                 f"{'local' if where == 'local' else 'under Slurm'}")
        if ratios:
            rows.append([label, ", ".join(f"{name} {percent(r)}" for name, r in ratios.items()), ratio_target])
        elif where == "slurm":
            rows.append([label, f"not measured: {m.get('slurm', 'skipped')}", ratio_target])
    if "analysis_job_wall_slurm_s" in m:
        rows.append(["analysis job wall per snapshot inside a Slurm allocation",
                     seconds(m["analysis_job_wall_slurm_s"]), ""])
    return lines_with_provenance(table(header, rows), [("workflow_overhead", record)])


def commands_table(recs: dict) -> str:
    import command_time  # bench/command_time.py: the commands it times

    rows, used = [], []
    for name, spec in command_time.COMMANDS.items():
        record = recs.get(f"command_time-{name}")
        command = spec["command"].format(scratch="$(mktemp -d)", venv=".venv")
        what = f"{spec['what']}: `{command}`" + (" in a fresh clone" if spec.get("fresh_clone") else "") + \
            (" (with this checkout's venv)" if "{venv}" in spec["command"] else "")
        if not measured(record):
            rows.append([what, not_measured(record, f"bench/command_time.py {name}")])
            continue
        used.append((f"command_time-{name}", record))
        m = record["measured"]
        result = f"; {m['summary']}" if m.get("summary") else ""
        rows.append([what, f"{seconds(m['wall_s'])} (CPU {seconds(m['cpu_s'])}){result}"])
    return lines_with_provenance(table(["command", "measured"], rows), used)


def import_dry_run_table(recs: dict) -> str:
    record = recs.get("import_dry_run")
    if not measured(record):
        return not_measured(record, "bench/import_dry_run.py --baseline CHECKOUT") + "\n"
    m, peer = record["measured"], record.get("peer")
    header = ["", "this tree" + (" / baseline (`--baseline`)" if peer else "")]
    rows = []
    for key, what in (("first_call", "`snakemake -n`, first call (no source records yet)"),
                      ("later_call", "`snakemake -n`, a later call"),
                      ("parse_first", "the config's parse alone (`checked_config`), first call"),
                      ("parse_later", "the config's parse alone, a later call")):
        def cell(result):
            part = result[key]
            wall = part["wall_s"] if "wall_s" in part else part["seconds"]
            return f"{seconds(wall)}, {part['peak_mb']} MB"
        rows.append([what, cell(m) + (f" / {cell(peer)}" if peer else "")])
    body = [f"A generated 2D LAMMPS run of {m['atoms_dump_lines']:,} lines ({m['atoms_dump_mb']} MB) in its atoms "
            "dump, with its pairs dump (wall time, peak resident memory):", "", *table(header, rows)]
    return lines_with_provenance(body, [("import_dry_run", record)])


def measured_records(recs: dict, keep, command: str) -> list[tuple[str, dict]] | str:
    """[(stem, record)] of the measured records whose stem `keep` accepts, in stem order, or, if there is none, the
    "not measured" line that names `command`."""
    found = sorted((stem, r) for stem, r in recs.items() if keep(stem))
    used = [(stem, record) for stem, record in found if measured(record)]
    return used or not_measured(found[-1][1] if found else None, command) + "\n"


def latest_record(recs: dict, prefix: str, command: str) -> tuple[str, dict] | str:
    """(stem, record) of the last measured record whose stem starts with `prefix`, else the "not measured" line that
    names `command`."""
    used = measured_records(recs, lambda stem: stem.startswith(prefix), command)
    return used if isinstance(used, str) else used[-1]


def dem_ab_table(recs: dict) -> str:
    """The latest A/B of the DEM step loop (bench/dem_ab.py): after / before throughput per case, pairs alternated."""
    latest = latest_record(recs, "dem_ab-", "bench/dem_ab.py BEFORE_CHECKOUT --pairs 8 --cpu 1")
    if isinstance(latest, str):
        return latest
    stem, record = latest
    settings, m = record["settings"], record["measured"]
    rows = [[case.upper(), fixed(m[case]["ratio_median"], 4),
             f"{fixed(m[case]['ratio_min'], 3)} – {fixed(m[case]['ratio_max'], 3)}", str(len(m[case]["ratios"]))]
            for case in DEM_CASES if case in m]
    body = [f"`{record['variant']}`: the record's tree (after) against the checkout it names as before (both in the "
            f"record's settings), {settings['steps']} steps a run, each run pinned to CPU {settings['cpu']}, runs "
            "alternated:", "",
            *table(["case", "after / before (median)", "range over the pairs", "pairs"], rows)]
    return lines_with_provenance(body, [(stem, record)])


def dem_particle_order_table(recs: dict) -> str:
    """Our step with the particles in the order a state was made against relabelled along a Morton curve
    (bench/dem_particle_order.py): throughput of each and their ratio per case, runs alternated."""
    record = recs.get("dem_particle_order")
    if not measured(record):
        return not_measured(record, "bench/dem_particle_order.py") + "\n"
    rows = []
    for case in DEM_CASES:
        m = record["measured"].get(case)
        if m:
            runs = ", ".join(f"{r:.3f}" for r in m["ratio_runs"])
            rows.append([f"{case.upper()} Hertz, N = {m['N']}", sci(m["as_made"]), sci(m["morton"]),
                         f"**{m['ratio']:.3f}** (runs: {runs})"])
    body = table(["state (of `bench/dem_vs_lammps.py`)", "as made (particle-steps per CPU-s)", "Morton order",
                  "Morton / as made"], rows)
    return lines_with_provenance(body, [("dem_particle_order", record)])


def dem_ab_states_table(recs: dict) -> str:
    """The latest in-process A/B of the DEM step kernels on a campaign record's states (bench/dem_ab_states.py):
    µs per step of each tree, before / after per state, whether the trajectories stayed identical."""
    latest = latest_record(recs, "dem_ab_states-", "bench/dem_ab_states.py BEFORE_CHECKOUT --cpu 1")
    if isinstance(latest, str):
        return latest
    stem, record = latest
    settings, m = record["settings"], record["measured"]
    rows = [[f"{rho} ({row['Z']:.2f})", f"{row['before_us_per_step']:.1f}", f"{row['after_us_per_step']:.1f}",
             f"**{row['speedup_median']:.3f}** "
             f"({row['speedup_quartiles'][0]:.3f} – {row['speedup_quartiles'][1]:.3f})",
             "identical" if row["identical"] else "differ"] for rho, row in m.items()]
    first = next(iter(m.values()))
    body = [f"`{record['variant']}`: the record's tree (after) against the checkout it names as before, on states of "
            f"the campaign record {settings['record']} (N = {first['N']}), {settings['repeat']} turns of "
            f"{settings['steps']} steps per tree and state, in one process pinned to CPU {settings['cpu']}:", "",
            *table(["ρ (Z)", "before (µs per step, CPU)", "after", "before / after (quartiles)", "trajectories"],
                   rows)]
    return lines_with_provenance(body, [(stem, record)])


def paper_run_ab_table(recs: dict) -> str:
    """A paper-size run made by two trees side by side (bench/paper_run_ab.py): CPU-hours of each whole run."""
    used = measured_records(recs, lambda stem: stem.startswith("paper_run_ab-"),
                            "bench/paper_run_ab.py BEFORE_CHECKOUT")
    if isinstance(used, str):
        return used
    rows = []
    for stem, record in used:
        settings, m = record["settings"], record["measured"]
        differ = m["snapshots_differ"]
        recorded = m["record_differs"]["after"]
        rows.append([f"{settings['system']} {settings['realization']} (N = {m['particles']}, {m['snapshots']} states)",
                     f"{m['cpu_hours']['before']:.3f}", f"{m['cpu_hours']['after']:.3f}",
                     f"**{m['cpu_hours']['before'] / m['cpu_hours']['after']:.2f}**",
                     "identical" if not differ else f"{len(differ)} variables differ",
                     "no record" if recorded is None else ("identical" if not recorded
                                                           else f"{len(recorded)} variables differ")])
    body = table(["run", "before (CPU-hours)", "after", "before / after", "snapshots, after against before",
                  "against the committed record"], rows)
    return lines_with_provenance(body, used)


TABLES = {"lammps_same_state": same_state_table, "dem_vs_lammps": dem_vs_lammps_table,
          "dem_scaling": dem_scaling_table, "dem_profile": dem_profile_table,
          "analysis": analysis_table, "p1_table": p1_table_table,
          "workflow_overhead": workflow_table, "commands": commands_table, "import_dry_run": import_dry_run_table,
          "dem_ab": dem_ab_table, "dem_particle_order": dem_particle_order_table,
          "dem_ab_states": dem_ab_states_table, "paper_run_ab": paper_run_ab_table,
          "dem_profile_record": dem_profile_record_table}


def render(page: str, recs: dict) -> str:
    """`page` with every marked table rewritten from `recs` ({file stem: record})."""
    def replace(match: re.Match) -> str:
        name = match.group("name")
        if name not in TABLES:
            raise KeyError(f"unknown table marker bench:{name} (known: {', '.join(TABLES)})")
        return match.group(1) + TABLES[name](recs) + match.group(4)
    return MARKER.sub(replace, page)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", type=Path, default=PAGE)
    ap.add_argument("--results", type=Path, default=records.RESULTS)
    ap.add_argument("--check", action="store_true", help="write nothing; exit 1 when the page is out of date")
    args = ap.parse_args(argv)
    old = args.page.read_text(encoding="utf-8")
    new = render(old, records.read_records(args.results))
    if args.check:
        if new != old:
            sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), new.splitlines(True), str(args.page),
                                                       "from the records"))
            return 1
        return 0
    if new != old:
        args.page.write_text(new, encoding="utf-8")
        print(f"{args.page}: tables rewritten from {args.results}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
