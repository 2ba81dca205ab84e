"""Test tiers (tests/conftest.py): plain pytest collects the unit tier alone, and a test that uses a build fixture is
in the workflow tier whatever its markers; `--all` (the README's test command, which .ci/run runs) collects every
tier."""
from __future__ import annotations

import re
import subprocess
import sys

from conftest import REPO


def collected(*args: str) -> set[str]:
    result = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-n0", "-p", "no:cacheprovider",
                             *args], cwd=REPO, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return {line for line in result.stdout.splitlines() if "::" in line}


def test_plain_pytest_is_the_unit_tier_and_all_adds_the_others():
    files = ["tests/test_damping_series.py", "tests/test_workflow_campaign.py", "tests/test_tiers.py"]
    unit, every = collected(*files), collected("--all", *files)
    # test_damping_series carries no marker, but one of its tests uses the smoke build: that one leaves the unit tier
    uses_the_build = "tests/test_damping_series.py::test_a_run_without_its_aggregate_is_read_from_its_own_analyses"
    assert uses_the_build in every and uses_the_build not in unit
    assert any(test.startswith("tests/test_damping_series.py::") for test in unit)
    assert not any(test.startswith("tests/test_workflow_campaign.py::") for test in unit)
    assert unit < every and "tests/test_tiers.py::test_plain_pytest_is_the_unit_tier_and_all_adds_the_others" in unit


def test_ci_runs_exactly_the_readmes_test_command():
    readme = (REPO / "README.md").read_text()
    commands = re.findall(r"^python3 -m venv .*pytest.*$", readme, flags=re.MULTILINE)
    assert len(commands) == 1 and commands[0].endswith("python -m pytest --all")
    assert commands[0] in (REPO / ".ci" / "run").read_text().splitlines()
