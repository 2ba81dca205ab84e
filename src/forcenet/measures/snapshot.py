"""Every single-snapshot measure of P1/P2 in one call, as named numpy arrays for the storage layer."""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from forcenet.measures.clusters import ClusterCurves, cluster_curves
from forcenet.measures.forces import coordination_number, force_pdf
from forcenet.measures.persistence_stats import essential_counts, persistence_bin_counts, total_persistence
from forcenet.network.force_network import ForceNetwork
from forcenet.topology.betti import betti_curves, default_thresholds
from forcenet.topology.persistence import PersistenceDiagrams, persistence_diagrams


@dataclass(frozen=True)
class SnapshotMeasures:
    """Measures of one force network. T thresholds, B force bins, K = d homology dimensions (0..d−1).

    Attributes
    ----------
    dim, n_particles : d and N of the snapshot.
    thresholds : (T,) F_th [⟨F⟩].
    betti : (K, T) B_k(F_th) (P1 §5.1).
    clusters : ClusterCurves — its (T,) arrays are also readable here by name: cluster_count,
        cluster_particle_count, edge_count, cluster_mean_size ⟨S⟩ (P1 §4.2), percolates, percolating_count,
        percolating_size N_per (P1 §4.3), largest_cluster_size, shape_parameter S̄_p (P1 §5.2),
        shape_parameter_cluster_mean.
    force_bin_edges : (B + 1,) [⟨F⟩]; force_pdf : (B,) [⟨F⟩⁻¹] (P1 §4.1).
    Z, Z_no_rattlers : mean contacts per particle, all particles / network particles only.
    mean_force : ⟨F⟩ [m̄ d_ave τ_c⁻²].
    persistence_bin_count : (5,) PD0 points per bin, order `PERSISTENCE_BINS` (P1 §5.3).
    total_persistence : (K,) TP_k over finite points [⟨F⟩]; essential_count : (K,) never-dying classes.
    diagrams : PersistenceDiagrams (birth ≥ death, death −inf for never-dying).
    """

    dim: int
    n_particles: int
    thresholds: np.ndarray
    betti: np.ndarray
    clusters: ClusterCurves
    force_bin_edges: np.ndarray
    force_pdf: np.ndarray
    Z: float
    Z_no_rattlers: float
    mean_force: float
    persistence_bin_count: np.ndarray
    total_persistence: np.ndarray
    essential_count: np.ndarray
    diagrams: PersistenceDiagrams

    def __getattr__(self, name: str):
        # only reached for names that are not fields: the cluster curves, read by name
        if name in _CLUSTER_FIELDS:
            return getattr(self.clusters, name)
        raise AttributeError(name)

    def as_dict(self) -> dict[str, np.ndarray]:
        """Plain dict of numpy arrays/scalars: the cluster curves flattened in by name, the diagrams flattened
        to diagram_homology_dim, birth, death, essential (one entry per point)."""
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in ("clusters", "diagrams")}
        out.update({name: getattr(self.clusters, name) for name in _CLUSTER_FIELDS})
        out.update(diagram_homology_dim=self.diagrams.homology_dim, birth=self.diagrams.birth,
                   death=self.diagrams.death, essential=self.diagrams.essential)
        return {name: np.asarray(value) for name, value in out.items()}


_CLUSTER_FIELDS = tuple(f.name for f in fields(ClusterCurves) if f.name != "thresholds")


def compute_snapshot_measures(network: ForceNetwork, *, thresholds=None, force_bin_edges=None,
                              percolation_axes=None, diagrams: PersistenceDiagrams | None = None,
                              fill_tetrahedra: bool = True) -> SnapshotMeasures:
    """All single-snapshot measures of one force network.

    Parameters
    ----------
    network : ForceNetwork (forces in ⟨F⟩).
    thresholds : (T,) F_th grid [⟨F⟩]; default 0 to 3 by 0.05.
    force_bin_edges : (B + 1,) PDF bins [⟨F⟩]; default 0 to 6 by 0.1.
    percolation_axes : axes whose opposite walls count for percolation (default all).
    diagrams : precomputed `persistence_diagrams(network)`, if any.
    fill_tetrahedra : fill the 4-cliques of a 3D flag complex (``analysis.fill_tetrahedra``; False: each is an
        enclosed void of B2, `forcenet.topology.persistence_diagrams`); no effect in 2D. Unused with `diagrams`.
    """
    thresholds = default_thresholds() if thresholds is None else np.asarray(thresholds, dtype=np.float64)
    diagrams = persistence_diagrams(network, fill_tetrahedra=fill_tetrahedra) if diagrams is None else diagrams
    max_dim = network.dim - 1
    pdf, bin_edges = force_pdf(network, force_bin_edges)
    return SnapshotMeasures(
        dim=network.dim, n_particles=network.n_particles, thresholds=thresholds,
        betti=betti_curves(diagrams, thresholds, max_dim),
        clusters=cluster_curves(network, thresholds, percolation_axes=percolation_axes),
        force_bin_edges=bin_edges, force_pdf=pdf,
        Z=coordination_number(network, include_rattlers=True),
        Z_no_rattlers=coordination_number(network, include_rattlers=False),
        mean_force=network.mean_force, persistence_bin_count=persistence_bin_counts(diagrams, 0),
        total_persistence=total_persistence(diagrams, max_dim), essential_count=essential_counts(diagrams, max_dim),
        diagrams=diagrams)
