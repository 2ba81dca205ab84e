"""Contacts of one snapshot → the force network that every topological measure reads.

A force network (P1 §3 "Interaction networks", P2 §III A) is a set of particles (vertices) and the
particle–particle contacts that carry a positive force (edges), each edge weighted by a force magnitude in
units of that network's mean force ⟨F⟩. Walls are not vertices; which particles touch which wall is kept so
that percolation (a cluster touching two opposite walls, P1 §4) can be decided.

Decisions the papers leave open (recorded with the others in docs/decisions.md, "Analysis"):

- A *contact* is a particle–particle pair whose total force |F_n + F_t| is positive. Rattlers and the
  coordination number are decided on contacts, whatever force kind the network is weighted by, so that the
  normal and the tangential networks of one snapshot share their particles.
- An *edge* is a contact whose force of the requested kind is positive (P2 §III A: only f > 0 enters).
- ⟨F⟩ is the mean of that kind's positive magnitudes over all particle–particle contacts, rattlers included
  (P1 §3: "rescaled by the average force in an interaction network"); it is the physical mean force.
- Rattlers (P1 §3 "Data pre-processing": particles with one or no contacts) are removed in ONE pass by
  default (``"once"``): the literal reading of P1, which keeps the open chains P1 §5.2 finds below jamming
  (S_p ≈ (N_L − 1)/N_L). ``"iterative"`` strips dangling chains until every particle has ≥ 2 contacts (the
  2-core); ``"none"`` keeps every particle, as P2 §III C does (rattlers then appear as components born at 0).
  After a removal, particles left without any edge of the requested kind are dropped as well: they carry
  no force of that kind and would otherwise count as clusters born at zero force.
- Wall contacts do not count toward the rattler rule unless ``count_wall_contacts=True``: the network's
  vertices are particles, and P1 counts contacts between particles.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from forcenet.boxes import period_matrix
from forcenet.datasets.schema import FORCE_KINDS
from forcenet.systems import RATTLER_RULES, resolve_rattler_rule  # noqa: F401 — the config's rules, applied here

#: what each rule does, in words (recorded next to the rule in every analysis file)
RATTLER_RULE_DESCRIPTIONS = {
    "once": "particles with <= 1 particle contact removed in one pass (P1 §3), then particles without an edge "
            "of the network's kind",
    "iterative": "particles with <= 1 particle contact removed until none is left (2-core), then particles "
                 "without an edge of the network's kind",
    "none": "every particle kept: rattlers and particles with only zero-force contacts are components born at "
            "the zero level of PD0 (P2 §III C)",
}


@dataclass(frozen=True)
class ForceNetwork:
    """Force network of one snapshot: arrays indexed by original particle ids.

    Attributes
    ----------
    dim : spatial dimension d (2 or 3).
    n_particles : N, all particles of the snapshot (rattlers included) — the N of P1's B_k/N, ⟨S⟩/N.
    position : ndarray, shape (N, d) — particle centres [d_ave].
    particle_mask : ndarray, shape (N,), bool — particles that are vertices of the network (not rattlers, and
        with at least one edge of this kind when rattlers are removed).
    non_rattler : ndarray, shape (N,), bool — particles that are not rattlers by the contact rule alone
        (the same for every force kind of a snapshot): the particles of Z without rattlers.
    edge_i, edge_j : ndarray, shape (E,), int64 — edge end points, ``edge_i < edge_j``, both in the mask,
        pairs in lexicographic order (an invariant that `compact` and the flag complex rely on).
    force : ndarray, shape (E,) — edge force in units of ⟨F⟩ (dimensionless, > 0).
    mean_force : ⟨F⟩ [m̄ d_ave τ_c⁻²], mean positive magnitude of this kind over all particle contacts.
    kind : "total" (|F_n + F_t|, P1), "normal" or "tangential" (P2).
    wall_particle, wall_id : ndarray, shape (W,), int64 — wall contacts of network particles; wall ids
        0 x_lo, 1 x_hi, 2 y_lo, 3 y_hi[, 4 z_lo, 5 z_hi].
    contact_i, contact_j : ndarray, shape (C,), int64 — every particle–particle contact (total force > 0),
        rattlers' included: the contact network behind the coordination number Z.
    rattler_rule : "once", "iterative" or "none" (see module docstring).
    period : ndarray, shape (d, d), or None — the edge vector of each periodic axis as a row (tilted in a
        triclinic box), zero rows on the bounded ones [d_ave]; None for a bounded box (our engine's). An edge then
        joins nearest images (`forcenet.boxes`), and a cluster percolates along a periodic axis by winding around
        it (`forcenet.measures.clusters`).
    """

    dim: int
    n_particles: int
    position: np.ndarray
    particle_mask: np.ndarray
    non_rattler: np.ndarray
    edge_i: np.ndarray
    edge_j: np.ndarray
    force: np.ndarray
    mean_force: float
    kind: str
    wall_particle: np.ndarray
    wall_id: np.ndarray
    contact_i: np.ndarray
    contact_j: np.ndarray
    rattler_rule: str
    period: np.ndarray | None = None

    @property
    def n_edges(self) -> int:
        return int(self.edge_i.size)

    @property
    def n_kept(self) -> int:
        """Number of network particles (vertices)."""
        return int(np.count_nonzero(self.particle_mask))

    @property
    def n_contacts(self) -> int:
        """Particle–particle contacts (total force > 0), all particles."""
        return int(self.contact_i.size)

    @property
    def n_contacts_without_rattlers(self) -> int:
        """Contacts between two particles that are not rattlers."""
        return int(np.count_nonzero(self.non_rattler[self.contact_i] & self.non_rattler[self.contact_j]))

    @property
    def kept_particles(self) -> np.ndarray:
        """Original ids of the network particles, shape (n_kept,), increasing."""
        return np.flatnonzero(self.particle_mask)

    @cached_property
    def compact(self) -> "CompactGraph":
        """The network on compact vertex ids, with vertex values (computed once per network, then cached):
        what the flag complex and the cluster statistics both read."""
        return compact_graph(self)


@dataclass(frozen=True)
class CompactVertices:
    """Vertices on compact ids 0..V−1, the network particles in increasing id order: the base of a network's graph
    (`CompactGraph`) and of the complexes built on it (`forcenet.topology.FlagComplex`).

    particle : ndarray, shape (V,), int64 — original particle id of each compact vertex.
    """

    particle: np.ndarray

    @property
    def n_vertices(self) -> int:
        return int(self.particle.size)


@dataclass(frozen=True)
class CompactGraph(CompactVertices):
    """A force network's graph on compact vertex ids (`CompactVertices`).

    Attributes (after ``particle``)
    -------------------------------
    index : ndarray, shape (N,), int64 — compact id of each original particle, −1 when not a vertex.
    edges : ndarray, shape (E, 2), int64 — compact end points, ``a < b``, lexicographically sorted (the order
        of the network's ``edge_i``, ``edge_j``).
    force : ndarray, shape (E,), float64 — edge forces [⟨F⟩].
    vertex_value : ndarray, shape (V,), float64 — max force of each vertex's edges, 0 without edges
        (`vertex_values`).
    """

    index: np.ndarray
    edges: np.ndarray
    force: np.ndarray
    vertex_value: np.ndarray


def vertex_values(n_vertices: int, edges: np.ndarray, edge_value: np.ndarray) -> np.ndarray:
    """f(vertex) = max over incident edges (P2 §III A), 0 for a vertex without edges; shape (n_vertices,)."""
    value = np.zeros(n_vertices, dtype=np.float64)
    np.maximum.at(value, edges[:, 0], edge_value)
    np.maximum.at(value, edges[:, 1], edge_value)
    return value


def compact_graph(network: ForceNetwork) -> CompactGraph:
    """`ForceNetwork.compact` (read that: it is cached).

    Relies on the edge invariant of every ForceNetwork (`_assemble` sorts the edges, `restrict_to_region`
    keeps a subset in order): ``edge_i < edge_j``, pairs in lexicographic order; the compact ids keep the
    order of the original ids, so the compact edges are sorted too. The invariant is checked (O(E)).
    """
    edge_i, edge_j = network.edge_i, network.edge_j
    step_i = np.diff(edge_i)
    if not (np.all(edge_i < edge_j) and np.all((step_i > 0) | ((step_i == 0) & (np.diff(edge_j) > 0)))):
        raise ValueError("ForceNetwork edges must have edge_i < edge_j and be sorted lexicographically")
    particle = network.kept_particles
    index = np.full(network.n_particles, -1, dtype=np.int64)
    index[particle] = np.arange(particle.size)
    edges = np.stack([index[edge_i], index[edge_j]], axis=1).reshape(-1, 2)
    force = np.asarray(network.force, dtype=np.float64)
    return CompactGraph(particle=particle, index=index, edges=edges, force=force,
                        vertex_value=vertex_values(particle.size, edges, force))


def drop_edgeless(keep: np.ndarray, edge_i: np.ndarray, edge_j: np.ndarray, rule: str) -> np.ndarray:
    """`keep` without the particles that have no edge among (edge_i, edge_j), unless ``rule == "none"``.

    After a rattler removal, particles left without any edge of the network's kind carry no force of that
    kind and would otherwise count as clusters born at zero force (module docstring); with rattlers kept
    ("none") every particle stays a vertex.
    """
    if rule == "none":
        return keep
    has_edge = np.zeros(keep.size, dtype=bool)
    has_edge[edge_i] = True
    has_edge[edge_j] = True
    return keep & has_edge


def force_magnitude(force_normal: np.ndarray, force_tangential: np.ndarray, kind: str) -> np.ndarray:
    """Per-contact force magnitude of one kind.

    Parameters
    ----------
    force_normal, force_tangential : ndarray, shape (C, d) — contact force vectors [force].
    kind : "total" → |F_n + F_t| (P1 §3), "normal" → |F_n|, "tangential" → |F_t| (P2 §IV).

    Returns
    -------
    ndarray, shape (C,) [force].
    """
    if kind == "total":
        vector = force_normal + force_tangential
    elif kind == "normal":
        vector = force_normal
    elif kind == "tangential":
        vector = force_tangential
    else:
        raise ValueError(f"kind must be one of {FORCE_KINDS}, got {kind!r}")
    return np.sqrt(np.einsum("cd,cd->c", vector, vector))


def rattler_free_mask(n_particles: int, contact_i: np.ndarray, contact_j: np.ndarray, rule: str,
                      extra_contacts: np.ndarray | None = None) -> np.ndarray:
    """Particles that are not rattlers (P1 §3: a rattler has at most one contact).

    Parameters
    ----------
    n_particles : N.
    contact_i, contact_j : ndarray, shape (C,) — contacts (each pair once).
    rule : "once" (one pass), "iterative" (repeat until every kept particle has ≥ 2 contacts among kept
        particles, i.e. the 2-core) or "none" (every particle kept).
    extra_contacts : ndarray, shape (N,), optional — contacts to add to each particle's count that never
        disappear (wall contacts when they count).

    Returns
    -------
    ndarray, shape (N,), bool.
    """
    extra = np.zeros(n_particles, dtype=np.int64) if extra_contacts is None else extra_contacts
    keep = np.ones(n_particles, dtype=bool)
    if rule == "none":
        return keep
    while True:
        alive = keep[contact_i] & keep[contact_j]
        count = (np.bincount(contact_i[alive], minlength=n_particles)
                 + np.bincount(contact_j[alive], minlength=n_particles) + extra)
        new_keep = keep & (count >= 2)
        if rule == "once" or np.array_equal(new_keep, keep):
            return new_keep
        keep = new_keep


def build_force_network(position, contact_i, contact_j, force_normal, force_tangential=None, *,
                        kind: str = "total", remove_rattlers: bool | str = True, wall_particle=None,
                        wall_id=None, wall_force=None, n_particles: int | None = None,
                        count_wall_contacts: bool = False, period=None) -> ForceNetwork:
    """The force network of one snapshot (P1 §3, P2 §III A).

    Parameters
    ----------
    position : array, shape (N, d) — particle centres [d_ave].
    contact_i, contact_j : int arrays, shape (C,) — particle–particle contacts, each pair at most once.
    force_normal, force_tangential : arrays, shape (C, d) — contact force vectors [force];
        ``force_tangential=None`` means frictionless (zero).
    kind : "total" |F_n + F_t| (P1), "normal" or "tangential" (P2).
    remove_rattlers : True (= "once"), False (= "none"), "once" or "iterative" (module docstring).
    wall_particle, wall_id : int arrays, shape (W,) — particle–wall contacts; ids 0..2d−1 ordered
        (x_lo, x_hi, y_lo, y_hi[, z_lo, z_hi]).
    wall_force : array, shape (W, d) or (W,), optional — wall contact forces; contacts with zero force are
        dropped when given.
    n_particles : N (default ``len(position)``).
    count_wall_contacts : whether wall contacts count toward the rattler rule (default False).
    period : array, shape (d,) or (d, d), optional — box lengths of the periodic axes, 0 on the bounded ones, or
        edge vectors as rows (`forcenet.datasets.snapshot.periodic_vectors`: a triclinic box) [d_ave]; None
        (default) for a bounded box.

    Returns
    -------
    ForceNetwork, forces in units of its mean ⟨F⟩.
    """
    position = np.asarray(position, dtype=np.float64)
    if position.ndim != 2 or position.shape[1] not in (2, 3):
        raise ValueError(f"position must have shape (N, 2) or (N, 3), got {position.shape}")
    dim = position.shape[1]
    n_particles = len(position) if n_particles is None else int(n_particles)
    contact_i, contact_j = _contact_pairs(contact_i, contact_j, n_particles)
    force_normal = np.asarray(force_normal, dtype=np.float64).reshape(len(contact_i), dim)
    force_tangential = (np.zeros_like(force_normal) if force_tangential is None
                        else np.asarray(force_tangential, dtype=np.float64).reshape(len(contact_i), dim))
    total = force_magnitude(force_normal, force_tangential, "total")
    magnitude = total if kind == "total" else force_magnitude(force_normal, force_tangential, kind)
    wall_particle, wall_id = _wall_contacts(wall_particle, wall_id, wall_force, n_particles, dim)
    return _assemble(dim, n_particles, position, contact_i, contact_j, total, magnitude, kind,
                     resolve_rattler_rule(remove_rattlers), wall_particle, wall_id, count_wall_contacts,
                     period=_period(period, dim))


def network_from_edge_forces(edge_i, edge_j, force, *, dim: int = 2, n_particles: int | None = None,
                             position=None, wall_particle=None, wall_id=None, remove_rattlers: bool | str = False,
                             normalise: bool = False, period=None) -> ForceNetwork:
    """A force network from scalar edge forces (hand-built test networks, synthetic benchmarks).

    Parameters
    ----------
    edge_i, edge_j : int arrays, shape (E,) — edges, each pair at most once.
    force : array, shape (E,) — edge force magnitudes; edges with force ≤ 0 are dropped.
    dim : spatial dimension recorded in the network (decides the homology dimensions computed).
    n_particles : N (default: largest index + 1, or ``len(position)``).
    position : array, shape (N, dim), optional [d_ave] (zeros when absent).
    wall_particle, wall_id : wall contacts as in `build_force_network`.
    remove_rattlers : as in `build_force_network`; default False keeps the graph exactly as given.
    normalise : divide by the mean positive force (default False: forces used as given, ⟨F⟩ reported).
    period : a periodic box as in `build_force_network` (default None: bounded).
    """
    edge_i = np.asarray(edge_i, dtype=np.int64).reshape(-1)
    edge_j = np.asarray(edge_j, dtype=np.int64).reshape(-1)
    if n_particles is None:
        n_particles = (len(position) if position is not None
                       else int(max(edge_i.max(initial=-1), edge_j.max(initial=-1)) + 1))
    position = (np.zeros((n_particles, dim)) if position is None
                else np.asarray(position, dtype=np.float64).reshape(n_particles, dim))
    edge_i, edge_j = _contact_pairs(edge_i, edge_j, n_particles)
    force = np.asarray(force, dtype=np.float64).reshape(-1)
    if force.shape != edge_i.shape:
        raise ValueError("force must have one value per edge")
    wall_particle, wall_id = _wall_contacts(wall_particle, wall_id, None, n_particles, dim)
    return _assemble(dim, n_particles, position, edge_i, edge_j, force, force, "total",
                     resolve_rattler_rule(remove_rattlers), wall_particle, wall_id, False, normalise=normalise,
                     period=_period(period, dim))


def _period(period, dim: int) -> np.ndarray | None:
    """A periodic box as edge-vector rows (d, d) (`forcenet.boxes.period_matrix`: box lengths (d,) are an orthogonal
    box's); None stays None (bounded). A bounded axis has a zero row, a periodic one its edge vector, which may be
    tilted only toward the lower axes (LAMMPS's restricted triclinic form)."""
    if period is None:
        return None
    given = np.asarray(period, dtype=np.float64)
    if given.shape not in ((dim,), (dim, dim)):
        raise ValueError(f"period must hold {dim} box lengths >= 0 (0 on a bounded axis) or {dim} edge vectors, "
                         f"got shape {given.shape}")
    vectors = period_matrix(given, dim)
    length = np.diag(vectors)
    if (not np.all(np.isfinite(vectors)) or np.any(length < 0) or np.any(vectors[length == 0])
            or np.any(np.triu(vectors, 1))):
        raise ValueError(f"period must hold {dim} box lengths >= 0 (0 on a bounded axis), or edge vectors in LAMMPS's "
                         f"triclinic form (zero rows on bounded axes, no entry above the diagonal), got {given.tolist()}")
    return vectors


def _contact_pairs(contact_i, contact_j, n_particles: int) -> tuple[np.ndarray, np.ndarray]:
    contact_i = np.asarray(contact_i, dtype=np.int64).reshape(-1)
    contact_j = np.asarray(contact_j, dtype=np.int64).reshape(-1)
    if contact_i.shape != contact_j.shape:
        raise ValueError("contact_i and contact_j must have the same length")
    if contact_i.size:
        if min(contact_i.min(), contact_j.min()) < 0 or max(contact_i.max(), contact_j.max()) >= n_particles:
            raise ValueError("contact index out of range [0, n_particles)")
        if np.any(contact_i == contact_j):
            raise ValueError("a contact joins a particle to itself")
        key = np.minimum(contact_i, contact_j) * n_particles + np.maximum(contact_i, contact_j)
        if np.unique(key).size != key.size:
            raise ValueError("a particle pair appears in more than one contact")
    return contact_i, contact_j


def _wall_contacts(wall_particle, wall_id, wall_force, n_particles: int, dim: int):
    if (wall_particle is None) != (wall_id is None):
        raise ValueError("give both wall_particle and wall_id, or neither")
    if wall_particle is None:
        return np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
    wall_particle = np.asarray(wall_particle, dtype=np.int64).reshape(-1)
    wall_id = np.asarray(wall_id, dtype=np.int64).reshape(-1)
    if wall_particle.shape != wall_id.shape:
        raise ValueError("wall_particle and wall_id must have the same length")
    if wall_particle.size and (wall_particle.min() < 0 or wall_particle.max() >= n_particles):
        raise ValueError("wall_particle index out of range")
    if wall_id.size and (wall_id.min() < 0 or wall_id.max() >= 2 * dim):
        raise ValueError(f"wall ids must lie in 0..{2 * dim - 1}")
    if wall_force is not None:
        # (W, d) vectors or (W,) magnitudes; W may be 0 (no particle touches a wall yet)
        columns = -1 if wall_particle.size else 1
        wall_force = np.asarray(wall_force, dtype=np.float64).reshape(len(wall_particle), columns)
        carries_force = np.sqrt((wall_force ** 2).sum(axis=1)) > 0
        wall_particle, wall_id = wall_particle[carries_force], wall_id[carries_force]
    return wall_particle, wall_id


def _assemble(dim, n_particles, position, contact_i, contact_j, total, magnitude, kind, rule,
              wall_particle, wall_id, count_wall_contacts, *, normalise: bool = True,
              period: np.ndarray | None = None) -> ForceNetwork:
    """Rattlers, edges, normalisation (the decisions of the module docstring)."""
    is_contact = total > 0
    ci, cj = contact_i[is_contact], contact_j[is_contact]
    extra = np.bincount(wall_particle, minlength=n_particles) if count_wall_contacts else None
    non_rattler = rattler_free_mask(n_particles, ci, cj, rule, extra)

    carries = magnitude > 0
    mean_force = float(magnitude[carries].mean()) if carries.any() else 0.0
    is_edge = carries & non_rattler[contact_i] & non_rattler[contact_j]
    keep = drop_edgeless(non_rattler.copy(), contact_i[is_edge], contact_j[is_edge], rule)
    low = np.minimum(contact_i[is_edge], contact_j[is_edge])
    high = np.maximum(contact_i[is_edge], contact_j[is_edge])
    order = np.lexsort((high, low))
    force = magnitude[is_edge][order]
    if normalise and mean_force > 0:
        force = force / mean_force
    on_network_wall = keep[wall_particle]
    return ForceNetwork(
        dim=dim, n_particles=n_particles, position=position, particle_mask=keep, non_rattler=non_rattler,
        edge_i=low[order], edge_j=high[order], force=force, mean_force=mean_force, kind=kind,
        wall_particle=wall_particle[on_network_wall], wall_id=wall_id[on_network_wall],
        contact_i=ci, contact_j=cj, rattler_rule=rule, period=period)
