"""The repository stands alone: no file in it cites a document that a user's clone does not have.

The project's own decisions live in docs/decisions.md and its layout in docs/architecture.md; design notes kept
outside the repository (a design or style page, a shared folder next to the checkout) must not be cited from code,
docs, tests, configs or profiles, since a reader of the clone cannot follow the reference.
"""
from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# Assembled from parts so that this file does not match its own patterns (it is scanned like every other file).
OUTSIDE_REFERENCES = re.compile("|".join([
    r"\bDESIGN" + r"\.md\b",                  # the design page kept outside the repository
    r"\bSTYLE" + r"\.md\b",                   # the style page kept outside the repository
    r"\.\./" + r"shared\b",                   # the shared folder beside the checkout
    r"(?<![\w.-])/" + r"work/",               # absolute paths of the machine the project was developed on
]))

SKIPPED_DIRS = {".git", ".venv", "results", "__pycache__", ".snakemake", ".pytest_cache"}


def repository_files(root: Path) -> list[Path]:
    """The files of the checkout: those git tracks plus untracked ones it does not ignore (so a new file is checked
    before its first commit); outside a git checkout, every file below `root` except outputs and environments."""
    try:
        listed = subprocess.run(["git", "-C", str(root), "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                                capture_output=True, check=True, timeout=60).stdout.decode()
        paths = [root / name for name in listed.split("\0") if name]
    except (OSError, subprocess.SubprocessError):
        paths = [p for p in root.rglob("*") if not SKIPPED_DIRS.intersection(p.relative_to(root).parts)]
    return sorted(p for p in paths if p.is_file() and not p.is_symlink())


def text_lines(files: list[Path]):
    """(path, line number, line) for every line of the files that are text (binary files are left out)."""
    for path in files:
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            continue  # binary
        for number, line in enumerate(text.splitlines(), start=1):
            yield path, number, line


def outside_references(root: Path, files: list[Path]) -> list[str]:
    """'path:line: text' for every line of a text file that cites something outside the repository."""
    return [f"{path.relative_to(root)}:{number}: {line.strip()}" for path, number, line in text_lines(files)
            if OUTSIDE_REFERENCES.search(line)]


def test_no_file_of_the_repository_cites_a_document_outside_it():
    files = repository_files(ROOT)
    assert any(p.name == "decisions.md" for p in files) and len(files) > 50  # the listing did find the checkout
    assert outside_references(ROOT, files) == []


@pytest.mark.parametrize("line, cites_outside", [
    ("# the ILP scheduler stalls (../" "shared/DESIGN" ".md, 'Scale')", True),
    ('"""Decisions (DESIGN' '.md "Topology decisions")."""', True),
    ("Only numpy, numba and math are imported here (STYLE" ".md).", True),
    ("see /" "work/main/docs/decisions.md", True),
    ("# recorded in docs/decisions.md, \"Scale\"", False),
    ('script: "../scripts/analyze.py"', False),
    ("caption='../report/figure.rst'", False),
    ("a design note (DESIGN_NOTES.md is not a file we cite)", False),
])
def test_the_check_finds_a_citation_of_an_outside_document_and_only_that(tmp_path, line, cites_outside):
    source = tmp_path / "module.py"
    source.write_text(f"x = 1\n{line}\n", encoding="utf-8")
    (tmp_path / "image.png").write_bytes(b"\x89PNG\r\n\x1a\n\xff\xfe DESIGN" b".md")  # binary: not read as text
    found = outside_references(tmp_path, repository_files(tmp_path))
    assert found == ([f"module.py:2: {line.strip()}"] if cites_outside else [])
