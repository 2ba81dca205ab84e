"""Compiled kernels are cached per version of all kernel sources (`forcenet._numba.kernel_cache_dir`): numba's own
cache checks only the file of the function it compiled, so a kernel calling into an edited file would keep the old
callee's code."""
from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numba
import pytest

from forcenet import _numba

PACKAGE = Path(_numba.__file__).resolve().parent


def test_the_digest_follows_every_kernel_source_and_nothing_else(tmp_path):
    (tmp_path / "dem" / "_kernels").mkdir(parents=True)
    (tmp_path / "_numba.py").write_text("A = 1\n")
    (tmp_path / "dem" / "_kernels" / "law.py").write_text("B = 1\n")
    (tmp_path / "report.py").write_text("C = 1\n")
    first = _numba.kernel_sources_digest(tmp_path)
    (tmp_path / "report.py").write_text("C = 2\n")  # not a kernel source
    assert _numba.kernel_sources_digest(tmp_path) == first
    (tmp_path / "dem" / "_kernels" / "law.py").write_text("B = 2\n")  # a callee's file
    assert _numba.kernel_sources_digest(tmp_path) != first
    assert _numba.kernel_cache_dir(tmp_path, base=tmp_path / "cache").parent == tmp_path / "cache"


def test_every_kernel_module_is_a_kernel_source():
    sources = {path for pattern in _numba.KERNEL_SOURCES for path in PACKAGE.glob(pattern)}
    for path in PACKAGE.rglob("*.py"):
        if "@numba.njit" in path.read_text(encoding="utf-8"):
            assert path in sources, f"{path.relative_to(PACKAGE)} holds numba kernels but is not in KERNEL_SOURCES"


def test_the_dem_kernels_are_cached_in_the_folder_of_the_current_sources():
    from forcenet.dem._kernels import stepping

    assert numba.config.CACHE_DIR == str(_numba.kernel_cache_dir())
    assert Path(stepping.advance._cache._cache_path).is_relative_to(_numba.kernel_cache_dir())


CALLER = """
import sys
import numba
from pathlib import Path
sys.path.insert(0, {package!r})
if {keyed!r}:
    from forcenet._numba import kernel_cache_dir
    numba.config.CACHE_DIR = str(kernel_cache_dir(Path({kernels!r}), ("*.py",), base={cache!r}))
else:
    numba.config.CACHE_DIR = {cache!r}
sys.path.insert(0, {kernels!r})
from caller import twice
print(twice(1.0))
"""


@pytest.mark.slow
@pytest.mark.parametrize("keyed, expected_after_edit", [(True, "6.0"), (False, "2.0")])
def test_an_edited_callee_reaches_its_cached_caller_only_with_the_keyed_folder(tmp_path, keyed, expected_after_edit):
    kernels = tmp_path / "kernels"
    kernels.mkdir()
    (kernels / "callee.py").write_text("import numba\n\n@numba.njit(cache=True)\ndef scale(x):\n    return 2.0 * x\n")
    (kernels / "caller.py").write_text(textwrap.dedent("""
        import numba
        from callee import scale

        @numba.njit(cache=True)
        def twice(x):
            return scale(x)
        """))
    script = tmp_path / "run.py"
    script.write_text(CALLER.format(package=str(PACKAGE.parent), keyed=keyed, kernels=str(kernels),
                                    cache=str(tmp_path / "cache")))

    def run() -> str:
        return subprocess.run([sys.executable, str(script)], capture_output=True, text=True, check=True,
                              cwd=tmp_path).stdout.strip()

    assert run() == "2.0"
    (kernels / "callee.py").write_text("import numba\n\n@numba.njit(cache=True)\ndef scale(x):\n    return 6.0 * x\n")
    # numba's own cache (one fixed folder) keeps the caller compiled with the old callee: the stale result
    assert run() == expected_after_edit
