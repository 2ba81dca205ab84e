"""The DEM time step: `advance` runs many steps per call (one numba call per chunk, no allocation per step) —
Gear prediction, wall motion, contact forces (`contacts.py`, the same kernels that record a snapshot), Gear
correction, and the checks that stop a chunk (neighbour-list rebuild due, blow-up).

Arguments are the named tuples of `forcenet.dem.kernel_arguments` (see `contacts.py` for motion, bodies, pairs, walls,
law and loads), plus:

* gear (`Integrator`): position (5, N, d) and rotation (5, N, 1|3), the Gear scaled derivatives (`gear.py`);
  accel_position (N, d), accel_rotation (N, 1|3) = Δt²/2 · 1/m, 1/I per component; half_mass (N, d),
  half_inertia (N, 1|3) = ½ m, ½ I per component (0 for wall particles); dt = Δt [τ_c];
* walls (`Walls`) also: flat (bool), box_lo, box_hi (d,) the wall planes at shift 0, state = [shift, speed,
  shift_max, speed of the last step], escape_margin, and the rough-wall particles (slots n_mobile.., positions
  prescribed by the wall motion, never integrated): anchor (W, d), axis (W,), sign (W,);
* watch (`RebuildWatch`): reference_position (N, d) and reference_shift, the positions and wall shift at the last
  rebuild, and half_skin: a chunk stops once anything has moved further since.

Outside the pair loop the step streams the Gear values: the corrector of one step and the predictor of the next
are one pass that also clears the force sums (`gear.gear_correct_predict`), and the flat walls visit only the
(particle, wall) entries that can touch before the next rebuild (`contacts.wall_candidates`).
"""
import math

import numba
import numpy as np

from forcenet._numba import NJIT_DEM
from forcenet.dem._kernels.contacts import (MAX_OVERLAP_FRACTION, flat_wall_forces, new_pair_block, pair_forces_2d,
                                            pair_forces_3d, worst_pair_fraction)
from forcenet.dem._kernels.gear import gear_correct_predict, gear_predict, gear_unpredict, new_gear_block

# --- status codes returned by `advance` ------------------------------------------------------------------------
STATUS_DONE = 0          # all requested steps done
STATUS_REBUILD = 1       # a particle moved more than half the skin: rebuild the neighbour list
STATUS_NOT_FINITE = 2    # NaN or inf in a position or velocity
STATUS_OVERLAP = 3       # an overlap above MAX_OVERLAP_FRACTION of a diameter
STATUS_ESCAPED = 4       # a particle centre left the box


@numba.njit(**NJIT_DEM)
def advance(gear, motion, loads, bodies, pairs, walls, law, watch, n_steps, kinetic_energy, status):
    """Advance the system by up to n_steps Gear steps (predict, walls, forces, correct). The correction of one
    step and the prediction of the next are one pass (`gear_correct_predict`); the last prediction is undone
    (`gear_unpredict`) before returning, so between calls gear holds the corrected state.

    motion must be (gear.position[0], the work array of the velocities the forces see, the same for the spin,
    1/Δt): `gear_predict` fills the latter two (see there). loads (force, torque) are work arrays. The pairs are
    in any fixed order (the engine lists the pairs touching at the rebuild first); walls.entry_particle,
    walls.entry_wall are the flat-wall entries that can come into contact before the next rebuild
    (`wall_candidates` at the last rebuild with reach release band + skin + margin: until then nobody moves by
    more than half the skin, nor do the walls); the others are exactly those that `flat_wall_forces` would skip.

    Every wall sits walls.state[0] (shift) inward of box_lo / box_hi [d_ave] and moves inward at state[1]
    [d_ave/τ_c] until the shift reaches state[2]; the shift and the speed of the last step (state[3]) are updated
    in place. kinetic_energy (≥ n_steps,) receives the total kinetic energy after each step [m̄ d_ave² τ_c⁻²].
    Stops early after a step whose largest displacement since the last rebuild exceeds half the skin
    (STATUS_REBUILD) or that blew up. status (2,) int receives [code, particle index]. Returns the number of steps
    done. The rebuild and escape checks look at the predicted positions, the ones the next forces will see.
    """
    gear_position = gear.position
    gear_rotation = gear.rotation
    n_mobile = bodies.n_mobile
    force_velocity = motion.velocity
    force_spin = motion.spin
    force = loads.force
    torque = loads.torque
    state = walls.state
    box_lo = walls.box_lo
    box_hi = walls.box_hi
    flat_walls = walls.flat
    n_wall_particles = walls.anchor.shape[0]
    escape_margin = walls.escape_margin
    accel_position = gear.accel_position
    accel_rotation = gear.accel_rotation
    half_mass = gear.half_mass
    half_inertia = gear.half_inertia
    reference_position = watch.reference_position
    reference_shift = watch.reference_shift
    half_skin = watch.half_skin
    radius = bodies.radius
    dt = gear.dt
    dim = gear_position.shape[2]
    inv_dt = 1.0 / dt
    lo = np.empty(dim)
    hi = np.empty(dim)
    law_values = (law[0], law[1], law[2], law[3], law[4], law[5], law[6])  # LAW_*, see contacts.py
    pair_block = new_pair_block()  # the scratch of the 3D pair loop and of the Gear pass, once per call
    gear_block = new_gear_block()
    status[0] = STATUS_DONE
    status[1] = -1
    gear_predict(gear_position, n_mobile, force_velocity, force)
    gear_predict(gear_rotation, n_mobile, force_spin, torque, False)  # the angle is not integrated (`gear.py`)
    for step in range(n_steps):
        # the walls at t + Δt
        old_shift = state[0]
        shift = old_shift + state[1] * dt
        if shift > state[2]:
            shift = state[2]
        if shift < old_shift:
            shift = old_shift
        state[0] = shift
        wall_speed = (shift - old_shift) * inv_dt
        state[3] = wall_speed
        for k in range(dim):
            lo[k] = box_lo[k] + shift
            hi[k] = box_hi[k] - shift
        if n_wall_particles > 0:
            place_wall_particles(gear_position, force_velocity, n_mobile, walls, shift, wall_speed * dt)
        force[n_mobile:, :] = 0.0  # the wall particles' rows (the Gear pass cleared the mobile ones)
        torque[n_mobile:, :] = 0.0
        worst_wall = 0.0
        wall_particle = -1
        if flat_walls:
            worst_wall, wall_particle = flat_wall_forces(motion, bodies, walls, lo, hi, dt, loads, None)
        if dim == 2:
            worst_excess, worst_pair = pair_forces_2d(motion, bodies, pairs, law_values, dt, loads, None)
        else:
            worst_excess, worst_pair = pair_forces_3d(motion, bodies, pairs, law_values, dt, loads, None, pair_block)
        energy = (gear_correct_predict(gear_position, force, accel_position, half_mass, n_mobile, force_velocity,
                                       gear_block)
                  + gear_correct_predict(gear_rotation, torque, accel_rotation, half_inertia, n_mobile, force_spin,
                                         gear_block, False))
        kinetic_energy[step] = energy * inv_dt * inv_dt
        n_far, bad = check_positions(gear_position[0], reference_position, n_mobile, lo, hi, escape_margin,
                                     half_skin * half_skin)
        code, particle = _step_status(gear_position, bad, energy, worst_excess, worst_pair, pairs, radius, worst_wall,
                                      wall_particle, n_far, shift - reference_shift, half_skin)
        if code != STATUS_DONE:
            gear_unpredict(gear_position, n_mobile)  # back to the corrected state of this step
            gear_unpredict(gear_rotation, n_mobile, False)
            status[0] = code
            status[1] = particle
            return step + 1
    gear_unpredict(gear_position, n_mobile)
    gear_unpredict(gear_rotation, n_mobile, False)
    return n_steps


@numba.njit(**NJIT_DEM)
def _step_status(gear_position, bad, energy, worst_excess, worst_pair, pairs, radius, worst_wall, wall_particle,
                 n_far, wall_travel, half_skin):
    """Whether `advance` must stop after a step, and why: (status code, particle slot or −1). A particle outside
    the walls or not finite (`check_positions`), a non-finite energy, an overlap above MAX_OVERLAP_FRACTION of a
    diameter (pair or wall), or a displacement / wall travel beyond half the skin (rebuild)."""
    if bad >= 0:
        for k in range(gear_position.shape[2]):
            if not (math.isfinite(gear_position[0, bad, k]) and math.isfinite(gear_position[1, bad, k])):
                return STATUS_NOT_FINITE, bad
        return STATUS_ESCAPED, bad
    if not math.isfinite(energy):
        return STATUS_NOT_FINITE, -1
    worst_pair_overlap = worst_pair_fraction(worst_excess, worst_pair, pairs, radius)
    if worst_pair_overlap > MAX_OVERLAP_FRACTION or worst_wall > MAX_OVERLAP_FRACTION:
        return STATUS_OVERLAP, (pairs.i[worst_pair] if worst_pair_overlap >= worst_wall else wall_particle)
    if n_far > 0 or wall_travel > half_skin:
        return STATUS_REBUILD, -1
    return STATUS_DONE, -1


@numba.njit(**NJIT_DEM)
def check_positions(position, reference, n_mobile, lo, hi, escape_margin, limit_sq):
    """(how many particles moved by more than √limit_sq since the last rebuild, the first particle whose centre is
    not finite or lies outside [lo − margin, hi + margin], −1 if none).

    Counts, not a largest displacement and a first index: a count is a sum over the particles in any order, so
    LLVM vectorises the loop (four particles to an instruction); the first particle outside is looked for only when
    there is one (a blow-up). A NaN displacement counts as not moved, but its particle fails every bound."""
    x = position.reshape(-1)  # flat views: particle i's coordinates at d·i, d·i + 1, …
    r = reference.reshape(-1)
    if position.shape[1] == 2:
        n_far, n_outside = _count_moved_and_outside_2d(x, r, n_mobile, lo[0] - escape_margin, lo[1] - escape_margin,
                                                       hi[0] + escape_margin, hi[1] + escape_margin, limit_sq)
    else:
        n_far, n_outside = _count_moved_and_outside_3d(x, r, n_mobile, lo[0] - escape_margin, lo[1] - escape_margin,
                                                       lo[2] - escape_margin, hi[0] + escape_margin,
                                                       hi[1] + escape_margin, hi[2] + escape_margin, limit_sq)
    if n_outside == 0:
        return n_far, -1
    dim = position.shape[1]
    for i in range(n_mobile):
        for k in range(dim):
            if not (position[i, k] >= lo[k] - escape_margin and position[i, k] <= hi[k] + escape_margin):
                return n_far, i
    return n_far, -1


# The two loops below read flat views at unsigned offsets, test the bounds without short-circuit (a NaN coordinate
# fails every test) and only count: no branch and no dependency from one particle to the next.

@numba.njit(**NJIT_DEM)
def _count_moved_and_outside_2d(x, r, n_mobile, lo_x, lo_y, hi_x, hi_y, limit_sq):
    n_far = 0
    n_outside = 0
    for i in range(n_mobile):
        a = np.uint64(2 * i)
        b = a + np.uint64(1)
        px = x[a]
        py = x[b]
        dx = px - r[a]
        dy = py - r[b]
        d_sq = 0.0
        d_sq += dx * dx
        d_sq += dy * dy
        n_far += d_sq > limit_sq
        n_outside += not ((px >= lo_x) & (px <= hi_x) & (py >= lo_y) & (py <= hi_y))
    return n_far, n_outside


@numba.njit(**NJIT_DEM)
def _count_moved_and_outside_3d(x, r, n_mobile, lo_x, lo_y, lo_z, hi_x, hi_y, hi_z, limit_sq):
    n_far = 0
    n_outside = 0
    for i in range(n_mobile):
        a = np.uint64(3 * i)
        b = a + np.uint64(1)
        c = a + np.uint64(2)
        px = x[a]
        py = x[b]
        pz = x[c]
        dx = px - r[a]
        dy = py - r[b]
        dz = pz - r[c]
        d_sq = 0.0
        d_sq += dx * dx
        d_sq += dy * dy
        d_sq += dz * dz
        n_far += d_sq > limit_sq
        n_outside += not ((px >= lo_x) & (px <= hi_x) & (py >= lo_y) & (py <= hi_y) & (pz >= lo_z) & (pz <= hi_z))
    return n_far, n_outside


@numba.njit(**NJIT_DEM)
def place_wall_particles(gear_position, force_velocity, n_mobile, walls, shift, velocity_dt):
    """Rough walls at wall shift `shift` [d_ave], walls moving inward by velocity_dt (= v_wall Δt) per step.

    Wall particle w moves with its wall along the wall's axis (anchor + sign·shift) and, along the other axes,
    contracts affinely with the box about its centre (factor L(t)/L0, L = box_hi − box_lo − 2 shift), so the
    rough boundary shrinks uniformly and the corners never form a closing wedge. Positions go to
    gear_position[0], scaled velocities to gear_position[1] and force_velocity.
    """
    wall_anchor = walls.anchor
    wall_axis = walls.axis
    wall_sign = walls.sign
    box_lo = walls.box_lo
    box_hi = walls.box_hi
    dim = wall_anchor.shape[1]
    for w in range(wall_anchor.shape[0]):
        idx = n_mobile + w
        axis = wall_axis[w]
        for k in range(dim):
            if k == axis:
                gear_position[0, idx, k] = wall_anchor[w, k] + wall_sign[w] * shift
                gear_position[1, idx, k] = wall_sign[w] * velocity_dt
            else:
                length0 = box_hi[k] - box_lo[k]
                centre = 0.5 * (box_hi[k] + box_lo[k])
                offset = wall_anchor[w, k] - centre
                gear_position[0, idx, k] = centre + offset * (length0 - 2.0 * shift) / length0
                gear_position[1, idx, k] = -offset * 2.0 * velocity_dt / length0
            force_velocity[idx, k] = gear_position[1, idx, k]
