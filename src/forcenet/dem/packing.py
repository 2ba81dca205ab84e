"""Initial states (P1 §3, P2 App. A): particles on a square / cubic lattice with random velocities.

Sizes (reduced units, length d_ave, mass m̄):

* bidisperse (P1): diameters d_s and ratio·d_s, small:large = `small_to_large`:1 by number, d_s chosen so the
  number-mean diameter is 1: d_s = (s + 1) / (s + ratio) with s = small_to_large.
* polydisperse (P2): diameters uniform in [1 − r_p/2, 1 + r_p/2].
* masses ∝ d² in 2D (disks of a common thickness, P1: chosen so the mean mass is m̄) and ∝ d³ in 3D,
  normalised so the mean mass is exactly 1; moments of inertia m r²/2 (disk) and 2 m r²/5 (sphere).

Lattice: spacing = largest possible diameter + `LATTICE_GAP`, so no two particles overlap; as many sites per axis as
fit in the box (N = n_axis^d, the lattice centred in the box). With `SystemSpec.initial_state` of lattice ``"box"``
(P1 §3's start: ≈ 2000 disks on a square grid in a 50 × 50 d_ave box, ρ0 ≈ 0.645) the given number of sites per axis
is spread evenly over the whole box (spacing box_length / n_axis, the outer sites half a spacing from the walls);
neighbouring large particles may then overlap at t = 0 (2025 disks in 50 d_ave: 10 % of a large diameter), which the
dynamics resolve in the relaxation that precedes the first compression (`protocol.run_compression`). Species are
assigned to sites at random. Velocities: each component normal with standard deviation `initial_speed`, minus the
mean (zero total momentum); angular velocities 0. Every random draw comes from one `numpy.random.Generator`, in a
fixed order.

Rough walls (P2): each wall is a square grid (a row in 2D) of touching wall particles of diameter
`WALL_PARTICLE_DIAMETER` (monodisperse), centred `WALL_PARTICLE_DIAMETER/2` outside the wall plane, so the wall
plane (box_lo/box_hi) is tangent to them and ρ is measured in the same box as for flat walls. A wall's grid
spans the initial box plus one wall particle on each side (the corners stay closed); the grid moves with its
wall along the wall normal and contracts affinely with the box along the wall
(`_kernels.stepping.place_wall_particles`): with a rigid grid, a frictional particle wedged in a corner between
two walls' particles gets crushed as the corner pocket closes at the wall speed (measured: 20 % overlap at
ρ ≈ 0.58 with μ = 0.5).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

#: gap between neighbouring lattice sites beyond the largest diameter [d_ave]
LATTICE_GAP = 0.05
#: diameter of the rough-wall particles [d_ave]
WALL_PARTICLE_DIAMETER = 1.0


@dataclass(frozen=True)
class WallParticles:
    """Rough walls: anchor (Nw, d) centres at wall shift 0 [d_ave]; axis (Nw,) normal axis of the wall;
    sign (Nw,) +1 for a lower wall (moves towards +axis), −1 for an upper one; wall_id (Nw,) 2·axis + side;
    radius [d_ave]."""

    anchor: np.ndarray
    axis: np.ndarray
    sign: np.ndarray
    wall_id: np.ndarray
    radius: float


@dataclass(frozen=True)
class InitialPacking:
    """Particles at t = 0: position, velocity (N, d) [d_ave, d_ave/τ_c]; radius, mass (N,) [d_ave, m̄];
    box_lo, box_hi (d,) the wall planes [d_ave]; walls the rough-wall particles or None."""

    position: np.ndarray
    velocity: np.ndarray
    radius: np.ndarray
    mass: np.ndarray
    box_lo: np.ndarray
    box_hi: np.ndarray
    walls: WallParticles | None

    @property
    def dimension(self) -> int:
        return self.position.shape[1]

    @property
    def packing_fraction(self) -> float:
        return packing_fraction(self.radius, self.box_hi - self.box_lo)


def particle_volume(diameter, dimension: int):
    """Area (2D) or volume (3D) of disks / spheres of the given diameter(s)."""
    diameter = np.asarray(diameter, dtype=float)
    return math.pi * diameter ** 2 / 4.0 if dimension == 2 else math.pi * diameter ** 3 / 6.0


def packing_fraction(radius: np.ndarray, span: np.ndarray) -> float:
    """ρ: total particle area / volume over the box area / volume (span (d,) = box_hi − box_lo)."""
    span = np.asarray(span, dtype=float)
    return float(particle_volume(2.0 * radius, len(span)).sum() / np.prod(span))


def slab_share(offset_lo, offset_hi, radius, dimension: int) -> np.ndarray:
    """Share of each disk / sphere lying between two parallel lines / planes at signed distances `offset_lo` <
    `offset_hi` from its centre along their normal (arrays broadcast together; [d_ave]): the integral of the
    chord length (2D) or the slice area (3D) over the clipped interval, over the whole area / volume."""
    radius = np.asarray(radius, dtype=float)
    lo = np.clip(np.asarray(offset_lo, dtype=float), -radius, radius)
    hi = np.clip(np.asarray(offset_hi, dtype=float), -radius, radius)
    if dimension == 2:  # ∫ 2√(r² − u²) du = u√(r² − u²) + r² asin(u/r)
        def primitive(u):
            return u * np.sqrt(np.maximum(radius ** 2 - u ** 2, 0.0)) + radius ** 2 * np.arcsin(u / radius)
        return (primitive(hi) - primitive(lo)) / (math.pi * radius ** 2)

    def primitive(u):  # ∫ π(r² − u²) du
        return math.pi * (radius ** 2 * u - u ** 3 / 3.0)
    return (primitive(hi) - primitive(lo)) / (4.0 / 3.0 * math.pi * radius ** 3)


def bulk_packing_fraction(position: np.ndarray, radius: np.ndarray, box_lo: np.ndarray, box_hi: np.ndarray,
                          margin: float) -> float:
    """ρ of the inner box at least `margin` [d_ave] from every wall: the particle area / volume inside it over
    its area / volume [-]. position (N, d), radius (N,), box_lo/box_hi (d,) [d_ave].

    A particle cut by the inner box's faces counts with the product over the axes of its share inside each axis'
    slab (`slab_share`): exact when it is cut along one axis only, an approximation of order its share beyond an
    edge otherwise. NaN when the margin leaves no inner box."""
    position = np.asarray(position, dtype=float)
    radius = np.asarray(radius, dtype=float)
    lo = np.asarray(box_lo, dtype=float) + margin
    hi = np.asarray(box_hi, dtype=float) - margin
    if np.any(hi <= lo):
        return math.nan
    dimension = position.shape[1]
    share = np.ones(radius.shape)
    for axis in range(dimension):
        share *= slab_share(lo[axis] - position[:, axis], hi[axis] - position[:, axis], radius, dimension)
    return float((particle_volume(2.0 * radius, dimension) * share).sum() / np.prod(hi - lo))


def largest_diameter(system) -> float:
    """Largest diameter the size distribution can produce [d_ave]."""
    if system.size_distribution == "bidisperse":
        s, ratio = system.small_to_large, system.diameter_ratio
        return ratio * (s + 1.0) / (s + ratio)
    return 1.0 + 0.5 * system.polydispersity


def smallest_diameter(system) -> float:
    if system.size_distribution == "bidisperse":
        s, ratio = system.small_to_large, system.diameter_ratio
        return (s + 1.0) / (s + ratio)
    return 1.0 - 0.5 * system.polydispersity


def sites_per_axis(system) -> int:
    """Lattice sites along each axis of the initial box (N = sites_per_axis^d)."""
    if system.initial_state is not None and system.initial_state.lattice == "box":
        return int(system.initial_state.sites_per_axis)
    return int(math.floor(system.box_length / (largest_diameter(system) + LATTICE_GAP) + 1e-9))


def lattice_spacing(system) -> float:
    """Distance between neighbouring sites of the initial lattice [d_ave]: the largest diameter + `LATTICE_GAP`
    (no overlaps), or, for `initial_state.lattice` ``"box"``, the box side over the sites per axis."""
    if system.initial_state is not None and system.initial_state.lattice == "box":
        return system.box_length / sites_per_axis(system)
    return largest_diameter(system) + LATTICE_GAP


def initial_overlap(system) -> float:
    """Largest overlap of two neighbouring particles on the initial lattice, as a share of the largest diameter
    [-] (0 for the default lattice)."""
    largest = largest_diameter(system)
    return max(0.0, largest - lattice_spacing(system)) / largest


def draw_diameters(system, n: int, rng: np.random.Generator) -> np.ndarray:
    """Diameters (n,) [d_ave] of the system's size distribution, in random order."""
    if system.size_distribution == "bidisperse":
        s, ratio = system.small_to_large, system.diameter_ratio
        small = (s + 1.0) / (s + ratio)
        n_small = int(round(n * s / (1.0 + s)))
        diameters = np.where(np.arange(n) < n_small, small, ratio * small)
        return diameters[rng.permutation(n)]
    half_width = 0.5 * system.polydispersity
    return rng.uniform(1.0 - half_width, 1.0 + half_width, n)


def particle_masses(diameters: np.ndarray, dimension: int) -> np.ndarray:
    """Masses ∝ d² (2D) or d³ (3D), mean exactly 1 [m̄]."""
    mass = diameters ** dimension
    return mass / mass.mean()


def rough_walls(box_lo: np.ndarray, box_hi: np.ndarray,
                diameter: float = WALL_PARTICLE_DIAMETER) -> WallParticles:
    """Rough walls of touching monodisperse particles just outside each wall plane (see module docstring)."""
    dim = len(box_lo)
    radius = 0.5 * diameter
    anchors, axes, signs, ids = [], [], [], []
    for axis in range(dim):
        others = [k for k in range(dim) if k != axis]
        grids = []
        for k in others:
            count = int(math.ceil((box_hi[k] - box_lo[k] + diameter) / diameter)) + 1
            grids.append(box_lo[k] - radius + diameter * np.arange(count))
        for side, plane, sign in ((0, box_lo[axis] - radius, 1.0), (1, box_hi[axis] + radius, -1.0)):
            for coords in itertools.product(*grids):
                centre = np.empty(dim)
                centre[axis] = plane
                centre[others] = coords
                anchors.append(centre)
                axes.append(axis)
                signs.append(sign)
                ids.append(2 * axis + side)
    return WallParticles(anchor=np.array(anchors), axis=np.array(axes, dtype=np.int64),
                         sign=np.array(signs), wall_id=np.array(ids, dtype=np.int64), radius=radius)


def initial_packing(system, rng: np.random.Generator) -> InitialPacking:
    """The t = 0 state of a `SystemSpec`: lattice, sizes, masses, random velocities, walls."""
    dim = system.dimension
    n_axis = sites_per_axis(system)
    n = n_axis ** dim
    spacing = lattice_spacing(system)
    offset = 0.5 * (system.box_length - n_axis * spacing) + 0.5 * spacing
    axis_sites = offset + spacing * np.arange(n_axis)
    position = np.stack(np.meshgrid(*[axis_sites] * dim, indexing="ij"), axis=-1).reshape(-1, dim)
    diameters = draw_diameters(system, n, rng)
    velocity = rng.normal(0.0, system.initial_speed, (n, dim)) if system.initial_speed > 0 else np.zeros((n, dim))
    if n > 1:
        velocity -= velocity.mean(axis=0)
    box_lo = np.zeros(dim)
    box_hi = np.full(dim, float(system.box_length))
    walls = rough_walls(box_lo, box_hi) if system.walls == "rough" else None
    return InitialPacking(position=position, velocity=velocity, radius=0.5 * diameters,
                          mass=particle_masses(diameters, dim), box_lo=box_lo, box_hi=box_hi, walls=walls)
