"""One snapshot file → its force network: the one adapter between the DEM's snapshot datasets and `ForceNetwork`.

Every reader of snapshots that needs a network goes through `snapshot_network`: the analysis (`forcenet.pipeline`,
which records the network measures and diagrams), P2's tables and Fig. 1 (`forcenet.report.p2`) and P1's Fig. 1 and
the network movies (`forcenet.plotting`). So a figure draws exactly the edges the analysis measured when it is given
the same options: the rattler rule of its study (`forcenet.systems.study_rattler_rule`), the force kind and what the
wall contacts do.

Wall contacts (`WALL_CONTACTS`) never are edges (walls are not vertices); they can be

- ``"ignored"``: not read (the network has none; percolation cannot be decided);
- ``"kept"``: read, so that percolation (a cluster touching two opposite walls, P1 §4.3) can be decided, but not
  counted toward the rattler rule (P1 counts contacts between particles) — what the analysis does;
- ``"counted"``: read and counted toward the rattler rule (a particle with one particle contact and one wall
  contact is then no rattler).
"""
from __future__ import annotations

from forcenet.datasets.snapshot import periodic_vectors
from forcenet.network.force_network import ForceNetwork, build_force_network

#: what the wall contacts of a snapshot do in its network (module docstring)
WALL_CONTACTS = ("ignored", "kept", "counted")


def snapshot_network(snapshot, kind: str = "total", *, rattler_rule: bool | str,
                     wall_contacts: str = "kept") -> ForceNetwork:
    """The force network of one snapshot (P1 §3, P2 §III A), edge forces in units of its mean ⟨F⟩ of `kind`.

    Parameters
    ----------
    snapshot : an opened snapshot dataset (`forcenet.datasets.read_snapshot`): position (N, d) [d_ave],
        contact_i, contact_j (C,), force_normal, force_tangential (C, d) [m̄ d_ave τ_c⁻²], box_lo, box_hi (d,) when
        it records periodic axes (`forcenet.datasets.schema.PERIODIC_AXES_ATTR`), and, unless
        ``wall_contacts="ignored"``, wall_contact_particle, wall_contact_wall (W,), wall_contact_force (W, d).
    kind : "total" |F_n + F_t| (P1), "normal" or "tangential" (P2).
    rattler_rule : "once", "iterative" or "none" (True = "once", False = "none"; `forcenet.network.force_network`).
    wall_contacts : one of `WALL_CONTACTS` (module docstring); the analysis keeps them ("kept").

    Returns
    -------
    ForceNetwork.
    """
    if wall_contacts not in WALL_CONTACTS:
        raise ValueError(f"wall_contacts must be one of {WALL_CONTACTS}, got {wall_contacts!r}")
    walls = {}
    if wall_contacts != "ignored":
        walls = dict(wall_particle=snapshot["wall_contact_particle"].values,
                     wall_id=snapshot["wall_contact_wall"].values,
                     wall_force=snapshot["wall_contact_force"].values,
                     count_wall_contacts=wall_contacts == "counted")
    return build_force_network(snapshot["position"].values, snapshot["contact_i"].values,
                               snapshot["contact_j"].values, snapshot["force_normal"].values,
                               snapshot["force_tangential"].values, kind=kind, remove_rattlers=rattler_rule,
                               period=periodic_vectors(snapshot), **walls)
