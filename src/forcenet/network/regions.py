"""Parts of a force network inside a region of the box (P2 §III D, Tables II–III).

P2 divides the box into four equal blocks — bottom left, bottom right, top right, top left — and compares
the persistence diagrams block by block. A block's network is the *induced* subnetwork: the particles whose
centre lies in the block and the edges between two of them (an edge crossing the block boundary belongs to
neither block). Forces keep the whole network's normalisation ⟨F⟩, so that block diagrams are on the same
scale as the whole-box diagram and as each other.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from forcenet.boxes import fractional_coordinates
from forcenet.network.force_network import ForceNetwork, drop_edgeless

# P2 Tables II–III row order; each entry is (x half, y half): 0 = lower half, 1 = upper half
QUADRANTS = {
    "bottom left": (0, 0),
    "bottom right": (1, 0),
    "top right": (1, 1),
    "top left": (0, 1),
}


def restrict_to_region(network: ForceNetwork, inside: np.ndarray) -> ForceNetwork:
    """The subnetwork induced by the particles flagged in `inside`.

    Parameters
    ----------
    network : ForceNetwork.
    inside : ndarray, shape (N,), bool — particles of the region.

    Returns
    -------
    ForceNetwork with the same ⟨F⟩ and N, `particle_mask` restricted to the region, only edges with both
    ends in the region, only the region's wall contacts. When the network had rattlers removed, region
    particles left without an edge are dropped too (same rule as `build_force_network`).
    """
    inside = np.asarray(inside, dtype=bool).reshape(network.n_particles)
    keep = network.particle_mask & inside
    is_edge = keep[network.edge_i] & keep[network.edge_j]
    keep = drop_edgeless(keep, network.edge_i[is_edge], network.edge_j[is_edge], network.rattler_rule)
    on_region_wall = keep[network.wall_particle]
    return replace(network, particle_mask=keep, edge_i=network.edge_i[is_edge], edge_j=network.edge_j[is_edge],
                   force=network.force[is_edge], wall_particle=network.wall_particle[on_region_wall],
                   wall_id=network.wall_id[on_region_wall])


def quadrant_mask(position: np.ndarray, box_lo, box_hi, quadrant: str, tilt=None) -> np.ndarray:
    """Particles whose centre lies in one quarter of the box (split at the box centre in x and y).

    Parameters
    ----------
    position : ndarray, shape (N, d) [d_ave].
    box_lo, box_hi : array, shape (d,) — box corners [d_ave].
    quadrant : one of `QUADRANTS` ("bottom left", "bottom right", "top right", "top left"); underscores
        are accepted for spaces.
    tilt : tilt factors of a triclinic box (`forcenet.boxes`), or None (default) for an orthogonal one. A tilted
        box is split at half its edge vectors a and b (fractional coordinates 1/2): four equal parallelograms.

    Returns
    -------
    ndarray, shape (N,), bool. A centre exactly on a dividing line belongs to the upper/right block, so
    every particle lies in exactly one quadrant (also particles slightly outside the box).
    """
    name = quadrant.replace("_", " ")
    if name not in QUADRANTS:
        raise ValueError(f"quadrant must be one of {tuple(QUADRANTS)}, got {quadrant!r}")
    x_half, y_half = QUADRANTS[name]
    if tilt is not None and np.any(tilt):
        upper = fractional_coordinates(position, box_lo, box_hi, tilt)[:, :2] >= 0.5
    else:
        middle = 0.5 * (np.asarray(box_lo, dtype=np.float64)[:2] + np.asarray(box_hi, dtype=np.float64)[:2])
        upper = np.asarray(position)[:, :2] >= middle
    return (upper[:, 0] == bool(x_half)) & (upper[:, 1] == bool(y_half))


def restrict_to_quadrant(network: ForceNetwork, box_lo, box_hi, quadrant: str, tilt=None) -> ForceNetwork:
    """The subnetwork of one quarter of the box (P2 Tables II–III); see `restrict_to_region`."""
    return restrict_to_region(network, quadrant_mask(network.position, box_lo, box_hi, quadrant, tilt))
