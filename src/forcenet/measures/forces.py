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
