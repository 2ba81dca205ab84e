"""The one place for numba compilation options: every kernel is `@numba.njit(**NJIT)`, except the DEM
engine's (`forcenet.dem._kernels`), which are `@numba.njit(**NJIT_DEM)`, and the DEM contact law
(`forcenet.dem._kernels.law.contact_2d/3d`), which is `@numba.njit(**NJIT_DEM_INLINE)`.

`fastmath` stays off in NJIT: it would let LLVM assume no NaN/inf, which breaks the DEM's blow-up checks and
makes results depend on reassociation.

NJIT_DEM allows exactly one fast-math liberty, `contract`: a·b + c may be computed as one fused multiply-add
(one rounding instead of two). LLVM still may not assume away NaN or inf (`nnan`/`ninf` stay off), nor
reassociate or use reciprocals, so the blow-up checks keep working and a run is deterministic: the same machine
code on the same input gives the same bits every time (results can differ in the last bits between CPUs with
and without FMA, as the cached code is compiled for the host CPU). `error_model='numpy'` drops the Python
ZeroDivisionError check from every division: x/0 gives inf or NaN, which the blow-up checks catch. Together
about 15 % faster contact loops (measured, bench/dem_vs_lammps.py).

NJIT_DEM_INLINE also inlines the function into its callers in numba's own IR, before LLVM sees it, so each
contact loop is optimised as one piece, as if the law were written out in it (LLVM inlines the separately
optimised function too: measured 0 to 1 % slower on the 3D step, bench/dem_vs_lammps.py's state).

Where compiled kernels are cached: numba's on-disk cache checks only the source file of the function it compiled,
but a kernel compiles in the kernels it calls from other files (`stepping.advance` holds the wall and pair loops of
`contacts.py` and the law of `law.py`). Edit a callee's file and the caller's cache would keep running the old
callee: a kernel change that some runs did not see. So every cache lives in a folder named after a digest of all
kernel sources (`KERNEL_SOURCES`, `kernel_cache_dir`): a change to any of them compiles everything afresh. The
folder sits under `NUMBA_CACHE_DIR` when that is set, else under the user's cache folder
(`$XDG_CACHE_HOME/forcenet/numba`, `~/.cache/forcenet/numba`).
"""
import os
from pathlib import Path

import numba

from forcenet._digest import sources_digest

#: the files of every numba kernel and of the argument types in their signatures, relative to the package (globs)
KERNEL_SOURCES = ("_numba.py", "dem/_kernels/*.py", "dem/kernel_arguments.py", "measures/_kernels.py",
                  "topology/_matching.py")


def kernel_sources_digest(package: Path, patterns=KERNEL_SOURCES) -> str:
    """sha256 (16 hex digits) of the kernel sources `patterns` under `package`, names and contents."""
    return sources_digest(package, patterns)


def kernel_cache_dir(package: Path = Path(__file__).resolve().parent, patterns=KERNEL_SOURCES,
                     base: str | os.PathLike | None = None) -> Path:
    """The folder of the compiled kernels of `package` as its kernel sources are now: `base` (default
    `NUMBA_CACHE_DIR`, else the user's cache folder) / ``kernels-<digest>``."""
    if base is None:
        base = os.environ.get("NUMBA_CACHE_DIR") or Path(
            os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "forcenet" / "numba"
    return Path(base) / f"kernels-{kernel_sources_digest(package, patterns)}"


# before any kernel module decorates its functions: numba picks a function's cache folder when it is decorated
numba.config.CACHE_DIR = str(kernel_cache_dir())

NJIT = dict(cache=True, fastmath=False)
NJIT_DEM = dict(cache=True, fastmath={"contract"}, error_model="numpy")
NJIT_DEM_INLINE = dict(NJIT_DEM, inline="always")
