"""Cost model of a compression run: particle count, time steps, core-hours, memory.

Used for Slurm resources (workflow/rules/simulate.smk) and for the cost table of docs/cluster.md. The throughput
constant is measured by `bench/dem_scaling.py` (particle-steps per second on one core); the step count follows
from the protocol: wall travel at `wall_speed`, plus relaxation windows in the quasi-static protocol.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from forcenet.systems import SystemSpec

#: particle-steps per core-second of the DEM engine, kept below what bench/dem_scaling.py measures on this
#: project's 2-vCPU VMs (bench/results/dem_scaling-2d.json, -3d.json; the table in docs/performance.md) so that
#: estimates and the Slurm time limits derived from them err long
PARTICLE_STEPS_PER_SECOND = {2: 1.0e7, 3: 4.0e6}


@dataclass(frozen=True)
class SimulationCost:
    particles: int
    steps: int
    core_hours: float
    memory_mb: int


def estimated_particles(spec: SystemSpec) -> int:
    """Particles on the initial lattice of `forcenet.dem.packing` (exact, not an estimate); an imported system's
    particles in its first state."""
    from forcenet.dem.packing import sites_per_axis

    if getattr(spec, "particles", None) is not None:
        return int(spec.particles)
    return sites_per_axis(spec) ** spec.dimension


def _volume_fraction_of_box(spec: SystemSpec, particles: int) -> float:
    mean_volume = math.pi / 4 if spec.dimension == 2 else math.pi / 6  # d_ave = 1
    return particles * mean_volume / spec.box_length ** spec.dimension


def simulation_cost(spec: SystemSpec) -> SimulationCost:
    particles = estimated_particles(spec)
    rho_initial = _volume_fraction_of_box(spec, particles)
    # box side at the last grid ρ: L_end = L0 (ρ0/ρ_end)^(1/d); each wall travels (L0 − L_end)/2
    length_end = spec.box_length * (rho_initial / spec.rho_grid[-1]) ** (1 / spec.dimension)
    travel = max(0.0, (spec.box_length - length_end) / 2)
    steps = travel / spec.wall_speed / spec.time_step
    if spec.relaxation is not None:
        steps += len(spec.rho_grid) * min(spec.relaxation.max_steps, 3 * spec.relaxation.window_steps)
    seconds = particles * steps / PARTICLE_STEPS_PER_SECOND[spec.dimension]
    memory_mb = 500 + particles // 10
    return SimulationCost(particles, int(steps), seconds / 3600, memory_mb)


#: analysis kernels per snapshot and force kind, per particle [s]: docs/performance.md's targets (60 ms for 2000 disks,
#: 300 ms for 4000 spheres; bench/analysis.py measures 28 and 115 ms), so that estimates err long, plus netCDF
#: reading and writing (~0.1 s per snapshot, bench/workflow_overhead.py)
ANALYSIS_SECONDS_PER_PARTICLE = {2: 3e-5, 3: 7.5e-5}
ANALYSIS_IO_SECONDS = 0.15


def analysis_cost_seconds(spec: SystemSpec) -> float:
    """Seconds to analyse one realization's snapshots (three force kinds each), on one core."""
    per_snapshot = 3 * ANALYSIS_SECONDS_PER_PARTICLE[spec.dimension] * estimated_particles(spec) + ANALYSIS_IO_SECONDS
    return len(spec.rho_grid) * per_snapshot
