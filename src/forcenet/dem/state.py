"""The DEM state as named structures, and the checkpoint arrays written from them.

A `forcenet.dem.engine.Simulation` is four structures: `ParticleState` (the Gear derivatives and the bodies),
`ContactState` (the contact law and the Verlet list with its tangential springs), `WallState` (the walls' planes,
motion and springs, the rough-wall particles) and `Clock` (step and time step). Together they are everything that
determines the future of a run; whatever else the engine holds it derives from them (`engine.StepWork`). The
contact law's parameters (`ContactLaw`) are kept as the array of its LAW_* values, which the kernels read.

A checkpoint holds one array per field, named after the field (`checkpoint_arrays`, `from_checkpoint`): the
names are unique across the four structures, so a new field is checkpointed without a list to update. They are
the names checkpoints have always had, so a checkpoint of any earlier version with the current format reads as it
is. Units are reduced ones (length d_ave, mass m̄, time τ_c); N counts every slot (mobile particles first, then
rough-wall particles), d is the dimension, P the number of listed pairs, W the number of rough-wall particles.
"""
import dataclasses
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from forcenet.dem._kernels.law import (LAW_BETA, LAW_GAMMA_N, LAW_GAMMA_T, LAW_K_N, LAW_K_T, LAW_MU,
                                       LAW_RADIUS_SCALED, LAW_SIZE, LAW_WALL_STIFFNESS)


@dataclass(frozen=True)
class ContactLaw:
    """Contact law (P1 Eq. 1–3): F_n = k_n x^(1+β) − γ_n x^β m_eff v_n ≥ 0,
    F_t = −k_t x^β ξ' − γ_t x^β m_eff v_t capped at μ F_n.

    normal_stiffness k_n [m̄ d_ave^(−β) τ_c^(−2)], tangential_stiffness k_t [same], normal_damping γ_n and
    tangential_damping γ_t [d_ave^(−β) τ_c^(−1)], friction μ, beta β. radius_scaled: multiply every term by
    √R_eff (R_eff = r_i r_j/(r_i + r_j), r_i at a wall) as LAMMPS gran/hertz does — benchmark only.
    wall_stiffness_factor: k_n and k_t of a flat-wall contact over the pair's (1: walls of the particles' material).
    """

    normal_stiffness: float
    tangential_stiffness: float
    normal_damping: float
    tangential_damping: float
    friction: float
    beta: float
    radius_scaled: bool = False
    wall_stiffness_factor: float = 1.0

    def as_array(self) -> np.ndarray:
        """The LAW_* layout (checkpoints)."""
        law = np.zeros(LAW_SIZE)
        law[LAW_K_N] = self.normal_stiffness
        law[LAW_K_T] = self.tangential_stiffness
        law[LAW_GAMMA_N] = self.normal_damping
        law[LAW_GAMMA_T] = self.tangential_damping
        law[LAW_MU] = self.friction
        law[LAW_BETA] = self.beta
        law[LAW_RADIUS_SCALED] = 1.0 if self.radius_scaled else 0.0
        law[LAW_WALL_STIFFNESS] = self.wall_stiffness_factor
        return law

    @classmethod
    def from_array(cls, law: np.ndarray) -> "ContactLaw":
        return cls(normal_stiffness=float(law[LAW_K_N]), tangential_stiffness=float(law[LAW_K_T]),
                   normal_damping=float(law[LAW_GAMMA_N]), tangential_damping=float(law[LAW_GAMMA_T]),
                   friction=float(law[LAW_MU]), beta=float(law[LAW_BETA]),
                   radius_scaled=bool(law[LAW_RADIUS_SCALED]),
                   # a law array of checkpoints older than the wall factor has 7 values: walls of the particles'
                   wall_stiffness_factor=float(law[LAW_WALL_STIFFNESS]) if law.size > LAW_WALL_STIFFNESS else 1.0)


def wall_law(law: np.ndarray) -> np.ndarray:
    """The law of a flat-wall contact (LAW_SIZE,) from the pair's LAW_* array: k_n and k_t × LAW_WALL_STIFFNESS
    (walls of their own material: stiffer springs), the pair's damping and friction (P1 §2)."""
    walls = law.copy()
    walls[LAW_K_N] *= law[LAW_WALL_STIFFNESS]
    walls[LAW_K_T] *= law[LAW_WALL_STIFFNESS]
    return walls


@dataclass(eq=False)
class ParticleState:
    """The particles, per slot: gear_position (5, N, d) and gear_rotation (5, N, 1|3), the Gear scaled
    derivatives Δtᵏ/k! · dᵏ/dtᵏ of position [d_ave] and rotation angle [rad] (the angle itself, row 0, is not
    integrated: see `forcenet.dem._kernels.gear`); radius (N,) [d_ave]; inv_mass,
    inv_inertia (N,) [1/m̄, 1/(m̄ d_ave²)], 0 for rough-wall particles; of the n_mobile mobile particles (re-ordered
    by cell at each rebuild) mass (n_mobile,) [m̄] and particle_id (n_mobile,) int64, each slot's input index."""
    gear_position: np.ndarray
    gear_rotation: np.ndarray
    radius: np.ndarray
    mass: np.ndarray
    inv_mass: np.ndarray
    inv_inertia: np.ndarray
    particle_id: np.ndarray
    n_mobile: int


@dataclass(eq=False)
class ContactState:
    """The contacts: law (LAW_SIZE,) the contact law's LAW_* values (`forcenet.dem._kernels.law`); the Verlet list
    of the pairs closer than r_i + r_j + skin [d_ave] at the last rebuild, pair_i, pair_j (P,) int32 slots with
    i < j, and their Cundall–Strack springs spring (P, d) [d_ave]."""
    law: np.ndarray
    skin: float
    pair_i: np.ndarray
    pair_j: np.ndarray
    spring: np.ndarray


@dataclass(eq=False)
class WallState:
    """The walls: box_lo, box_hi (d,) their planes at shift 0 [d_ave] (±inf without walls); wall_state (4,) =
    [shift, speed, shift_max, speed of the last step] [d_ave, d_ave/τ_c]; flat_walls (else rough-wall particles
    or none) and the flat walls' springs wall_spring (n_mobile, 2d, d) [d_ave] (wall id 2·axis + side);
    escape_margin [d_ave] how far past a wall a centre may go; the rough-wall particles (slots n_mobile..):
    wall_anchor (W, d) [d_ave] at shift 0, wall_axis (W,) int64, wall_sign (W,) ±1, wall_id (W,) int64."""
    box_lo: np.ndarray
    box_hi: np.ndarray
    wall_state: np.ndarray
    flat_walls: bool
    wall_spring: np.ndarray
    escape_margin: float
    wall_anchor: np.ndarray
    wall_axis: np.ndarray
    wall_sign: np.ndarray
    wall_id: np.ndarray


@dataclass(eq=False)
class Clock:
    """step: steps done since t = 0; time_step: Δt [τ_c]."""
    step: int
    time_step: float


#: the structures a checkpoint is written from, in the order of its arrays
STATE_PARTS = (ParticleState, ContactState, WallState, Clock)


def checkpoint_arrays(*parts) -> dict:
    """{field name: value} of every field of the given state structures (for np.savez)."""
    return {field.name: getattr(part, field.name) for part in parts for field in dataclasses.fields(part)}


def from_checkpoint(part_type: type, arrays: Mapping[str, np.ndarray]):
    """The structure part_type read from `checkpoint_arrays` output or an np.load of it: arrays copied, the
    scalars (0-d arrays in a checkpoint) as the field's type. KeyError naming the first field it lacks."""
    values = {}
    for field in dataclasses.fields(part_type):
        if field.name not in arrays:
            raise KeyError(f"no array {field.name!r} (a field of {part_type.__name__})")
        value = arrays[field.name]
        values[field.name] = np.array(value) if field.type is np.ndarray else field.type(value)
    return part_type(**values)
