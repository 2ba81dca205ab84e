"""The layers of docs/architecture.md hold: each part of `src/forcenet/` imports only the layers listed before it, no
modules import each other in a circle, and numba kernels live apart from their drivers, importing only numpy, numba
and math.

Every import counts, including the lazy ones inside functions. A new top-level module or package must be placed in
`LAYERS` (and in the layer table of docs/architecture.md) before this passes.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "forcenet"

#: docs/architecture.md, "Layers", top to bottom: the top-level modules and packages of each layer
LAYERS = (
    ("foundations", {"__init__", "errors", "_digest", "_numba", "_lazy", "units", "boxes"}),
    ("data model", {"datasets"}),
    ("configuration", {"catalog", "systems"}),
    ("importers", {"importers"}),
    ("DEM engine", {"dem"}),
    ("configuration checks", {"checks", "cost", "workflow_io"}),
    ("network", {"network"}),
    ("topology", {"topology"}),
    ("measures", {"measures"}),
    ("report", {"report"}),
    ("plotting", {"plotting"}),
    ("workflow", {"pipeline", "pipeline_figures", "pipeline_p2", "campaign", "campaign_cli"}),
    ("research", {"research"}),
)
KERNEL_IMPORTS = {"__future__", "math", "numba", "numpy", "forcenet._numba"}


def part_of(path: Path) -> str:
    """The top-level module or package of `src/forcenet/` a file belongs to ('dem', 'units', …)."""
    relative = path.relative_to(PACKAGE)
    return relative.parts[0] if len(relative.parts) > 1 else relative.stem


def imported_modules(source: str) -> list[str]:
    """Every module a file imports, at any depth (`from forcenet import units` gives 'forcenet.units')."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            found.append(node.module)
            if node.module == "forcenet":
                found += [f"forcenet.{alias.name}" for alias in node.names]
    return found


def layering_problems(files: dict[str, str]) -> list[str]:
    """'part → imported part' for every import from a later layer (or of a part no layer lists); `files` maps a
    path below src/forcenet to its source."""
    rank = {part: index for index, (_, parts) in enumerate(LAYERS) for part in parts}
    problems = []
    for name, source in files.items():
        me = part_of(PACKAGE / name)
        if me not in rank:
            problems.append(f"{name}: '{me}' is in no layer (add it to LAYERS and docs/architecture.md)")
            continue
        for module in imported_modules(source):
            parts = module.split(".")
            if parts[0] != "forcenet" or len(parts) == 1:
                continue
            other = parts[1]
            if other not in rank and not (PACKAGE / other).is_dir() and not (PACKAGE / f"{other}.py").exists():
                other = "__init__"  # a name defined in forcenet/__init__.py (`from forcenet import __version__`)
            if other == me:
                continue
            if other not in rank or rank[other] > rank[me]:
                problems.append(f"{name}: {me} imports {module}")
    return problems


def kernel_problems(files: dict[str, str]) -> list[str]:
    """Modules that import numba must import nothing but numpy, numba, math, forcenet._numba and other kernel modules
    of their own kernel package (`forcenet.dem._kernels.*`: contact law, contacts, integrator, stepping)."""
    problems = []
    for name, source in files.items():
        modules = imported_modules(source)
        # forcenet._numba holds the options and the cache folder of the kernels, not a kernel: the standard library
        if name != "_numba.py" and any(m.split(".")[0] == "numba" for m in modules):
            problems += [f"{name}: a kernel module imports {m}" for m in modules
                         if m not in KERNEL_IMPORTS and m.split(".")[0] not in {"numba", "numpy"}
                         and not m.startswith("forcenet.dem._kernels.")]
    return problems


def package_sources() -> dict[str, str]:
    return {str(path.relative_to(PACKAGE)): path.read_text(encoding="utf-8") for path in sorted(PACKAGE.rglob("*.py"))}


def test_each_layer_imports_only_the_layers_before_it():
    sources = package_sources()
    assert {"dem/engine.py", "plotting/p1.py", "datasets/schema.py"} <= set(sources)
    assert layering_problems(sources) == []


def test_numba_kernels_import_only_numpy_numba_and_math():
    sources = package_sources()
    kernels = [name for name, source in sources.items()
               if any(m.split(".")[0] == "numba" for m in imported_modules(source))]
    assert {"dem/_kernels/law.py", "dem/_kernels/contacts.py", "dem/_kernels/gear.py", "dem/_kernels/stepping.py",
            "measures/_kernels.py", "topology/_matching.py"} <= set(kernels)
    assert kernel_problems(sources) == []


@pytest.mark.parametrize("name, source, problem", [
    ("network/force_network.py", "from forcenet.datasets.schema import FORCE_KINDS\n", None),
    ("network/force_network.py", "def f():\n    from forcenet.measures import clusters\n",
     "network/force_network.py: network imports forcenet.measures"),
    ("datasets/io.py", "from forcenet import units, plotting\n", "datasets/io.py: datasets imports forcenet.plotting"),
    ("checks.py", "from forcenet.dem import packing\n", None),  # a config is judged by the engine's own formulas
    ("dem/protocol.py", "def run():\n    from forcenet.checks import check_system\n",
     "dem/protocol.py: dem imports forcenet.checks"),
    ("systems.py", "def f():\n    from forcenet.importers.scan import file_record\n",
     "systems.py: systems imports forcenet.importers"),
    ("datasets/runs.py", "class A:\n    def f(self):\n        from forcenet.systems import format_rho\n",
     "datasets/runs.py: datasets imports forcenet.systems"),
    ("datasets/io.py", "from forcenet import __version__\n", None),  # a name of the package root
    ("systems.py", "from forcenet.dem import packing\n", "systems.py: systems imports forcenet.dem"),
    ("figures.py", "import numpy\n", "figures.py: 'figures' is in no layer"),
])
def test_the_layer_check_flags_an_upward_import(name, source, problem):
    problems = layering_problems({name: source})
    assert problems == [] if problem is None else (len(problems) == 1 and problems[0].startswith(problem))


@pytest.mark.parametrize("source, problem", [
    ("import math\n\nimport numba\nimport numpy as np\n\nfrom forcenet._numba import NJIT\n", None),
    ("import numba\nfrom numba import types\n", None),
    ("import numba\nimport xarray as xr\n", "k.py: a kernel module imports xarray"),
    ("import numba\nfrom forcenet.network import ForceNetwork\n", "k.py: a kernel module imports forcenet.network"),
    ("import xarray as xr\nfrom forcenet.network import ForceNetwork\n", None),  # a driver: no numba
])
def test_the_kernel_check_flags_a_kernel_importing_more_than_numpy_numba_math(source, problem):
    assert kernel_problems({"k.py": source}) == ([] if problem is None else [problem])



def module_of(name: str) -> str:
    """The dotted module of a file below src/forcenet ('report/p1_claims.py' → 'forcenet.report.p1_claims')."""
    parts = Path(name).with_suffix("").parts
    return ".".join(["forcenet", *(parts[:-1] if parts[-1] == "__init__" else parts)])


def import_graph(files: dict[str, str]) -> dict[str, set[str]]:
    """module → the package's modules it imports, at any depth of the file (a function-local import is an import);
    `from forcenet.report import p1_claims` counts as importing the submodule, a package's own face is skipped."""
    modules = {module_of(name) for name in files}
    graph = {}
    for name, source in files.items():
        me = module_of(name)
        targets = set()
        for node in ast.walk(ast.parse(source)):
            names = []
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                names = [f"{node.module}.{alias.name}" for alias in node.names] + [node.module]
            for candidate in names:
                if candidate in modules and candidate != me and not me.startswith(candidate + "."):
                    targets.add(candidate)
                    break
        graph[me] = targets
    return graph


def import_circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every set of modules that import each other in a loop (strongly connected, more than one), sorted."""
    index, low, stack, on_stack, circles, counter = {}, {}, [], set(), [], [0]

    def visit(node):  # Tarjan's algorithm
        index[node] = low[node] = counter[0]
        counter[0] += 1
        stack.append(node)
        on_stack.add(node)
        for other in graph.get(node, ()):
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in on_stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(circles)


def test_no_modules_import_each_other_in_a_circle():
    assert import_circles(import_graph(package_sources())) == []


def test_the_circle_check_sees_a_circle_hidden_in_a_function():
    files = {"a.py": "def f():\n    from forcenet.b import g\n", "b.py": "from forcenet import a\n",
             "c.py": "from forcenet.a import f\n"}
    assert import_circles(import_graph(files)) == [["forcenet.a", "forcenet.b"]]
    assert import_circles(import_graph({"a.py": "from forcenet.b import g\n", "b.py": "import math\n"})) == []
