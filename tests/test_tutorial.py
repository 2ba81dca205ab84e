"""docs/tutorial.py (a jupytext notebook) runs cell by cell in a Jupyter kernel against a smoke build's results,
so the tutorial cannot rot; its own asserts check what it reads (every snapshot has a cluster, F/⟨F⟩ averages 1,
d_B ≤ d_W2 ≤ d_W1, a diagram is at distance 0 from itself)."""
from __future__ import annotations

import jupytext
import pytest
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

from conftest import REPO

pytestmark = pytest.mark.workflow
TUTORIAL = REPO / "docs" / "tutorial.py"


def run_notebook(results, tmp_path, monkeypatch):
    notebook = jupytext.read(TUTORIAL)
    monkeypatch.setenv("FORCENET_RESULTS", str(results))
    NotebookClient(notebook, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()
    return notebook


def outputs(notebook) -> str:
    return "".join(out.get("text", "") for cell in notebook.cells if cell.cell_type == "code"
                   for out in cell.get("outputs", []))


def test_tutorial_runs_against_the_smoke_build(smoke_run, tmp_path, monkeypatch):
    notebook = run_notebook(smoke_run / "results", tmp_path, monkeypatch)
    text = outputs(notebook)
    for expected in ("B0/N =", "loaded contacts", "PD0:", "bottleneck:", "wasserstein_1:", "wasserstein_2:",
                     "rattler rule none: <F> = 1.70, PD0 never-dying classes 3, PD1 points 1"):  # §6, the table
        assert expected in text, text
    recorded = (REPO / "data/validation/manifest.csv").exists()
    assert "recorded runs in" in text and ("densest state:" in text) == recorded  # §7, the campaign records
    figures = sum(1 for cell in notebook.cells for out in cell.get("outputs", []) if "image/png" in out.get("data", {}))
    assert figures == 3  # B0/N(ρ), the force network, the persistence diagram


def test_tutorial_fails_without_results(tmp_path, monkeypatch):
    """An execution error in a cell fails the test (the tutorial is really run, not only parsed)."""
    with pytest.raises(CellExecutionError, match="network_measures.nc"):
        run_notebook(tmp_path / "no-results", tmp_path, monkeypatch)
