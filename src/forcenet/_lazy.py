"""Names of a package loaded from its submodules on first use (PEP 562), so that importing the package (or one
light submodule of it) does not import the heavy ones: `forcenet.datasets.paths` and `forcenet.importers.sources`
load without xarray when the workflow parses its config."""
from __future__ import annotations

import importlib
from typing import Any, Callable, Mapping


def lazy_exports(package: str, exports: Mapping[str, str],
                 namespace: dict[str, Any]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of `package` (its ``globals()`` is `namespace`): name →
    submodule in `exports`; a name is imported once, then kept in the namespace."""
    def __getattr__(name: str) -> Any:
        if name not in exports:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{exports[name]}"), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted([*namespace, *exports])

    return __getattr__, __dir__
