"""The global attributes each file kind's contract requires (`forcenet.datasets.schema`: REQUIRED_GLOBAL_ATTRS and
KIND_GLOBAL_ATTRS), for the datasets the tests build in memory: the readers index them (a file without one is refused
by its validated read), so a hand-made dataset carries them as a written file does."""
from __future__ import annotations

import json
import math
from typing import Any

import xarray as xr

from forcenet.datasets import provenance_attrs
from forcenet.datasets.schema import KIND_GLOBAL_ATTRS, REQUIRED_GLOBAL_ATTRS

#: a value of each kind's own attribute where a test does not give one (constants NaN: a system without a material)
KIND_ATTR_VALUES: dict[str, Any] = {
    "rattler_rule": "none", "force_law": "linear", "essential_convention": "minus_one", "simulation_sha256": "test",
    "force_unit_dyn": math.nan, "stiffness_scale_reduced": math.nan, "normal_stiffness_cgs": math.nan,
}


def contract_attrs(kind: str, *, system: str = "test", dimension: int = 2, realization: int = -1,
                   **values: Any) -> dict[str, Any]:
    """Every global attribute a file of `kind` must have: provenance (a recorded config with an empty entry of
    `system`), the spatial `dimension`, the flag complex that goes with it, `KIND_ATTR_VALUES`; `values` replace any."""
    attrs = provenance_attrs(system=system, realization=realization, seed=0, config={"systems": {system: {}}},
                             title=f"test {kind}")
    own = {**KIND_ATTR_VALUES, "dimension": dimension, "flag_complex": "triangles" if dimension == 2 else "tetrahedra"}
    attrs.update({key: own[key] for key in KIND_GLOBAL_ATTRS.get(kind, ()) if key in own})
    attrs.update(values)
    missing = [key for key in (*REQUIRED_GLOBAL_ATTRS, *KIND_GLOBAL_ATTRS.get(kind, ())) if key not in attrs]
    assert not missing, f"no test value for {kind}'s global attributes {missing}: give them as `values`"
    return attrs


def with_contract(ds: xr.Dataset, kind: str, **values: Any) -> xr.Dataset:
    """`ds` (changed in place and returned) with the global attributes of `kind` it lacks (`contract_attrs`, its
    system and dimension taken from its own attributes or its `spatial` size); those it has, and `values`, are kept."""
    dimension = int(ds.attrs.get("dimension", ds.sizes.get("spatial", 2)))
    system = str(ds.attrs.get("system", "test"))
    ds.attrs = {**contract_attrs(kind, system=system, dimension=dimension), **ds.attrs, **values}
    return ds


def record_settings(ds: xr.Dataset, **entry: Any) -> xr.Dataset:
    """`ds` (changed in place and returned) recording `entry` (friction, relaxation …) in its system's entry of the
    config it records (global attribute ``config``), where the reports read a run's settings."""
    config = json.loads(ds.attrs["config"])
    config.setdefault("systems", {}).setdefault(str(ds.attrs["system"]), {}).update(entry)
    ds.attrs["config"] = json.dumps(config, sort_keys=True, default=str)
    return ds
