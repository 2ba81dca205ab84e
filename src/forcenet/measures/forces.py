"""Force distribution and contact numbers of one network (P1 §4.1, §4.3; P2 §IV A)."""
from __future__ import annotations

import numpy as np

from forcenet.network.force_network import ForceNetwork

FORCE_PDF_MAX = 6.0  # [⟨F⟩]; config key analysis.force_pdf.max
FORCE_PDF_BINS = 60


def default_force_bin_edges(force_max: float = FORCE_PDF_MAX, n_bins: int = FORCE_PDF_BINS) -> np.ndarray:
    """Fixed PDF binning 0..force_max [⟨F⟩], shape (n_bins + 1,), so that snapshots share their bins."""
    return np.linspace(0.0, force_max, n_bins + 1)


def force_pdf(network: ForceNetwork, bin_edges=None) -> tuple[np.ndarray, np.ndarray]:
    """PDF(F) of the edge forces F/⟨F⟩ (P1 Fig. 3).

    Parameters
    ----------
    network : ForceNetwork.
    bin_edges : array, shape (B + 1,) [⟨F⟩]; default `default_force_bin_edges()`.

    Returns
    -------
    pdf : ndarray, shape (B,) [⟨F⟩⁻¹] — count per bin / (all edges × bin width): the integral over the bins
        is the fraction of edges inside the binning (forces beyond the last edge are not renormalised away).
    bin_edges : ndarray, shape (B + 1,).
    """
    bin_edges = default_force_bin_edges() if bin_edges is None else np.asarray(bin_edges, dtype=np.float64)
    counts, _ = np.histogram(network.force, bins=bin_edges)
    total = max(network.n_edges, 1)
    return counts / (total * np.diff(bin_edges)), bin_edges


def coordination_number(network: ForceNetwork, *, include_rattlers: bool = True) -> float:
    """Mean contact number Z (P1 §4.3 ⟨k⟩; P2 Fig. 6).

    Contacts are particle–particle contacts with positive total force (walls not counted), whatever force
    kind weights the network. With rattlers: Z = 2 C / N over all N particles (as the DEM reports it).
    Without: Z = 2 C' / N' over the N' particles that are not rattlers (the network's rattler rule), C' the
    contacts between two of them. 0 for an empty set.
    """
    if include_rattlers:
        return 2.0 * network.n_contacts / network.n_particles if network.n_particles else 0.0
    n_non_rattlers = int(np.count_nonzero(network.non_rattler))
    return 2.0 * network.n_contacts_without_rattlers / n_non_rattlers if n_non_rattlers else 0.0


#: the largest |net contact force| of a particle over the mean normal force a state relaxed to rest may show
#: (`force_imbalance`): the campaign's jammed states reach 3·10⁻⁴, a wall whose recorded stiffness was not the one
#: that moved the particles 3.8
FORCE_BALANCE_TOLERANCE = 1e-2


def net_contact_forces(n_particles: int, contact_i, contact_j, contact_force, wall_particle=(), wall_force=()):
    """The sum of the contact forces on each particle (n_particles, d) [force unit]: contact_force (C, d) acts on
    particle contact_i from contact_j and, by Newton's third law, its opposite on contact_j; wall_force (W, d) acts
    on wall_particle."""
    contact_force = np.asarray(contact_force, dtype=float)
    dimension = contact_force.shape[1] if contact_force.ndim == 2 else np.asarray(wall_force).shape[-1]
    net = np.zeros((n_particles, dimension))
    np.add.at(net, np.asarray(contact_i, dtype=int), contact_force)
    np.add.at(net, np.asarray(contact_j, dtype=int), -contact_force)
    if len(wall_particle):
        np.add.at(net, np.asarray(wall_particle, dtype=int), np.asarray(wall_force, dtype=float))
    return net


def force_imbalance(snapshot) -> tuple[float, int]:
    """(largest |net contact force| of a particle in contact over the mean normal force magnitude, that particle;
    NaN and −1 without contacts) of one snapshot (its arrays, `forcenet.datasets` snapshot contract). A state relaxed
    to rest is in mechanical equilibrium, so this is ~0 (the campaign's jammed states: ≤ 3·10⁻⁴); forces that
    moved the particles other than the recorded ones show up here."""
    contact_i = np.asarray(snapshot["contact_i"], dtype=int)
    contact_j = np.asarray(snapshot["contact_j"], dtype=int)
    if contact_i.size == 0:
        return float("nan"), -1
    normal = np.asarray(snapshot["force_normal"], dtype=float)
    net = net_contact_forces(len(snapshot["radius"]), contact_i, contact_j,
                             normal + np.asarray(snapshot["force_tangential"], dtype=float),
                             snapshot["wall_contact_particle"], snapshot["wall_contact_force"])
    touched = np.unique(np.concatenate([contact_i, contact_j, np.asarray(snapshot["wall_contact_particle"], int)]))
    relative = np.linalg.norm(net[touched], axis=1) / np.linalg.norm(normal, axis=1).mean()
    worst = int(np.argmax(relative))
    return float(relative[worst]), int(touched[worst])
