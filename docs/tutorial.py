# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # forcenet tutorial: from the build's outputs to a distance between two persistence diagrams
#
# This notebook reads what `snakemake --cores 2` wrote under `results/` (or the smoke build,
# `--configfile config/smoke.yaml`), with xarray and forcenet's public API only:
#
# 1. open a system's stacked network measures and select a realization, a packing fraction ρ and a force
#    threshold F_th;
# 2. plot the number of clusters B0/N versus ρ at one F_th;
# 3. load one DEM snapshot and draw its force network;
# 4. read a persistence diagram;
# 5. compute the bottleneck and Wasserstein distances between two diagrams;
# 6. your own data: import a state from a plain contact table and analyse it as a snapshot.
#
# It is a jupytext "percent" script: run it as `python docs/tutorial.py`, or open it as a notebook
# (`jupytext --to ipynb docs/tutorial.py`). `tests/test_tutorial.py` executes it against the smoke build, so
# it keeps working. Set `FORCENET_RESULTS` to read another results folder.

# %%
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from matplotlib.collections import LineCollection

from forcenet.datasets import diagram_points, open_dataset, paths
from forcenet.topology import PersistenceDiagrams, diagram_distances

RESULTS = Path(os.environ.get("FORCENET_RESULTS", "results"))
print("reading", RESULTS.resolve())

# %% [markdown]
# ## 1. Network measures of one system
#
# `results/{system}/network_measures.nc` stacks every snapshot's analysis over `realization` and `rho`. Every
# variable carries `units` and `long_name`; the global attributes record the config, seed, version and commit.

# %%
system = "2d_hertz"
measures = xr.open_dataset(paths.network_measures(RESULTS, system))  # every file's path: forcenet.datasets.paths
print(measures["betti"].attrs["long_name"], "[", measures["betti"].attrs["units"], "]")
print(dict(measures.sizes))
print("forcenet", measures.attrs["forcenet_version"], "commit", measures.attrs["git_commit"][:10])

# %% [markdown]
# Select by label: the first realization, the ρ nearest to 0.84, the total-force network and F_th = 1 ⟨F⟩
# (nearest grid value). `betti` has a `homology_dim` dimension: 0 counts clusters (B0), 1 loops (B1).

# %%
one = measures.sel(force_kind="total").isel(realization=0)
snapshot_rho = float(one["rho"].sel(rho=0.84, method="nearest"))
threshold = float(one["threshold"].sel(threshold=1.0, method="nearest"))
b0 = one["betti"].sel(homology_dim=0, rho=snapshot_rho, threshold=threshold)
n = int(one["n_particles"].sel(rho=snapshot_rho))
print(f"rho = {snapshot_rho:.3f}, F_th = {threshold:g} <F>: B0 = {int(b0)} clusters, B0/N = {float(b0) / n:.4f}")

# %% [markdown]
# ## 2. B0/N versus ρ at one threshold
#
# The mean over realizations of the clusters per particle, with the spread over realizations as a band.

# %%
b0_per_particle = measures["betti"].sel(force_kind="total", homology_dim=0, threshold=threshold) / measures["n_particles"]
mean = b0_per_particle.mean("realization")
spread = b0_per_particle.std("realization")
fig, ax = plt.subplots(figsize=(5, 3.5))
ax.plot(mean["rho"], mean, marker="o", label=rf"$F_{{th}}$ = {threshold:g} $\langle F\rangle$")
ax.fill_between(mean["rho"], mean - spread, mean + spread, alpha=0.2)
ax.set_xlabel(r"packing fraction $\rho$")
ax.set_ylabel(r"$B_0/N$")
ax.legend()
assert np.all(np.isfinite(mean.values)) and np.all(mean.values > 0)  # every snapshot has at least one cluster

# %% [markdown]
# ## 3. One snapshot and its force network
#
# `results/sim/{system}/r{NN}/rho{ρ}.nc` holds positions, radii and every contact with its normal and
# tangential force. P1 uses the total force |F_n + F_t|, in units of its mean ⟨F⟩.

# %%
snapshot = open_dataset(paths.snapshot(RESULTS, system, paths.realization_name(0), f"{snapshot_rho:.3f}"))
force = np.linalg.norm(snapshot["force_normal"].values + snapshot["force_tangential"].values, axis=1)
loaded = force > 0
relative = force[loaded] / force[loaded].mean()
position = snapshot["position"].values
i, j = snapshot["contact_i"].values[loaded], snapshot["contact_j"].values[loaded]
print(f"{snapshot.sizes['particle']} particles, {loaded.sum()} loaded contacts, Z = {float(snapshot['Z']):.2f}")

fig, ax = plt.subplots(figsize=(5, 5))
lines = LineCollection(np.stack([position[i], position[j]], axis=1), array=relative, cmap="viridis",
                       linewidths=0.5 + 2 * np.clip(relative / 3, 0, 1))
ax.add_collection(lines)
ax.set_xlim(snapshot["box_lo"].values[0], snapshot["box_hi"].values[0])
ax.set_ylim(snapshot["box_lo"].values[1], snapshot["box_hi"].values[1])
ax.set_aspect("equal")
ax.set_xlabel(r"$x$ [$d_{ave}$]")
ax.set_ylabel(r"$y$ [$d_{ave}$]")
fig.colorbar(lines, label=r"$F/\langle F\rangle$")
assert abs(relative.mean() - 1) < 1e-12

# %% [markdown]
# ## 4. A persistence diagram
#
# `results/{system}/diagrams.nc` stores every diagram as one flat `point` dimension: each point has its force
# kind (`diagram_force_kind`, an index into the `force_kind` coordinate), homology dimension, birth, death (−inf for
# classes that never die), realization and grid ρ. Forces decrease along the filtration (super-level sets), so
# birth ≥ death. `forcenet.datasets.diagram_points` selects one snapshot's diagram of one force kind.

# %%
diagrams = xr.open_dataset(paths.diagrams(RESULTS, system))
print("force kinds:", list(diagrams["force_kind"].values))  # total (P1), normal and tangential (P2)


def diagram_at(rho: float, kind: str = "total", realization: int = 0) -> PersistenceDiagrams:
    """All homology dimensions of one snapshot's diagram (`rho` on the config's grid), as PersistenceDiagrams."""
    points = diagram_points(diagrams, kind, realization=realization, rho=rho)
    return PersistenceDiagrams(homology_dim=points.homology_dim, birth=points.birth, death=points.death)


pd_here = diagram_at(snapshot_rho)
pd0 = pd_here.homology_dim == 0
print(f"PD0: {pd0.sum()} points, {np.sum(pd0 & pd_here.essential)} never die")
assert np.all(pd_here.birth[~pd_here.essential] >= pd_here.death[~pd_here.essential])

fig, ax = plt.subplots(figsize=(4, 4))
finite = pd0 & ~pd_here.essential
ax.scatter(pd_here.birth[finite], pd_here.death[finite], s=10, label="finite")
ax.scatter(pd_here.birth[pd0 & pd_here.essential], np.zeros(np.sum(pd0 & pd_here.essential)), marker="v",
           color="k", label="never dies (at 0)")
top = float(pd_here.birth[pd0].max()) * 1.05
ax.plot([0, top], [0, top], color="0.5", lw=0.8)
ax.set_xlabel(r"birth $b/\langle F\rangle$")
ax.set_ylabel(r"death $d/\langle F\rangle$")
ax.legend()

# %% [markdown]
# ## 5. Distance between two diagrams
#
# `forcenet.topology.diagram_distances` gives the bottleneck distance d_B and the Wasserstein distances
# d_W1, d_W2 (L∞ ground metric, P2 §III D) between the PD_k of two networks; never-dying classes get death −1
# (P2's convention, `essential="minus_one"`). Here: PD0 of the snapshot above and of the next denser one.

# %%
grid = diagrams["point_rho"].values
next_rho = float(np.min(grid[grid > snapshot_rho + 1e-9])) if np.any(grid > snapshot_rho + 1e-9) else float(np.max(grid[grid < snapshot_rho]))
pd_next = diagram_at(next_rho)
distances = diagram_distances(pd_here, pd_next, homology_dim=0)
for metric, value in distances.items():
    print(f"{metric}: {value:.4f} <F>")
assert distances["bottleneck"] <= distances["wasserstein_2"] + 1e-12 <= distances["wasserstein_1"] + 2e-12
assert diagram_distances(pd_here, pd_here, homology_dim=0)["wasserstein_1"] == 0.0  # a diagram is 0 from itself

# %% [markdown]
# ## 6. Your own data: a contact table or LAMMPS dumps
#
# Force networks from another code (LAMMPS) or an experiment (photoelastic disks) go through the same snapshot
# contract as our engine's (`forcenet.datasets.schema`: positions, radii, contact pairs, normal and tangential
# force vectors, wall contacts, box, dimension, ρ and the source files with their sha256). In a build, a config
# system with `source:` instead of the DEM settings imports them (`config/example_import.yaml`, README "Your own
# data"): `snakemake --cores 2 --configfile config/example_import.yaml`. Here the importer is called directly on
# the shipped hand-made table `data/examples/table_2d/` (a square of four disks carrying 2, a separate pair
# carrying 0.5, a lone disk; forces given as magnitudes).
#
# What the conventions mean for imported data:
#
# - forces are analysed in units of each network's mean ⟨F⟩, so the source's force unit does not matter (its
#   length unit sets ρ and the drawings);
# - a *contact* is a pair with a positive force; a LAMMPS pair row with zero force (a neighbour not touching) is
#   not imported;
# - rattlers: P1 removes particles with fewer than two contacts once (`"once"`), P2 keeps every particle
#   (`"none"`); a kept particle without contacts is a component of B0 (and a cluster) at F_th ≤ 0, and a
#   never-dying class of PD0;
# - thresholds F_th are in ⟨F⟩ (0 to 3 by default), super-level sets F ≥ F_th;
# - never-dying classes have death −∞ in the files; P2's distances give them death −1 ⟨F⟩ (`essential_convention`);
# - claims of P1 and P2 about their compression protocol (ρ_J, the regimes around it) are "not evaluated" for
#   imported states: the import records the states, not how they were made.

# %%
import forcenet
from forcenet.datasets.snapshot import snapshot_dataset
from forcenet.importers import table
from forcenet.network import snapshot_network
from forcenet.topology import persistence_diagrams

EXAMPLE = Path(forcenet.__file__).resolve().parents[2] / "data" / "examples" / "table_2d"
state = table.read_state(EXAMPLE / "particles.csv", EXAMPLE / "contacts.csv", dimension=2, forces="magnitudes",
                         box={"lo": [0, 0], "hi": [6, 4]})
imported = snapshot_dataset(attrs={"system": "my_table"}, **state.snapshot_arrays())  # the contract's arrays
print(f"{imported.sizes['particle']} particles, {imported.sizes['contact']} contacts, rho = {float(imported.rho):.3f}")
for rule in ("none", "once"):
    network = snapshot_network(imported, "total", rattler_rule=rule)
    pd = persistence_diagrams(network)
    never_dying = int(np.sum(np.isneginf(pd.death[pd.homology_dim == 0])))
    loops = int(np.sum(pd.homology_dim == 1))
    print(f"rattler rule {rule}: <F> = {network.mean_force:.2f}, PD0 never-dying classes {never_dying}, "
          f"PD1 points {loops}")
    assert loops == 1  # the square's loop, whatever the rattler rule

# %% [markdown]
# ## 7. A paper-size run from the campaign records
#
# The validation campaign's finished runs are committed under `data/validation/` (`data/validation/README.md`):
# one file per run holding every snapshot of its ρ grid (positions, radii, contacts with their force vectors, wall
# contacts, box, ρ, Z), listed in `manifest.csv`. Open one with xarray, see Z(ρ) of the whole run, and rebuild the
# snapshot of its densest state to analyse it as above. (`FORCENET_RECORDS=dir` reads another records folder; with
# no record yet this section says so.)

# %%
import pandas as pd

from forcenet.datasets.records import state_snapshot

RECORDS = Path(os.environ.get("FORCENET_RECORDS", Path(forcenet.__file__).resolve().parents[2] / "data" / "validation"))
manifest_path = Path(paths.record_manifest(RECORDS))
manifest = pd.read_csv(manifest_path) if manifest_path.exists() else pd.DataFrame()
print(f"{len(manifest)} recorded runs in {RECORDS}")
if len(manifest):
    row = manifest.iloc[0]
    record = xr.open_dataset(RECORDS / row["file"])
    print(f"{row['system']} {row['realization']}: N = {record.sizes['particle']}, {record.sizes['state']} states, "
          f"{row['cpu_hours']} CPU-hours, simulated at commit {str(row['git_commit'])[:12]}")
    for label, rho, z in zip(record["state"].values[::4], record["rho"].values[::4], record["Z"].values[::4]):
        print(f"  state {label}: rho = {rho:.4f}, Z = {z:.3f}")
    attrs, arrays = state_snapshot(record, record.sizes["state"] - 1)  # the densest state, as simulated
    densest = snapshot_dataset(attrs=attrs, **arrays)
    network = snapshot_network(densest, "total", rattler_rule="once")
    pd_densest = persistence_diagrams(network)
    print(f"densest state: {densest.sizes['contact']} contacts, PD1 points {int(np.sum(pd_densest.homology_dim == 1))}")
    assert float(densest.Z) == float(record["Z"].values[-1])  # the rebuilt snapshot is the recorded state
