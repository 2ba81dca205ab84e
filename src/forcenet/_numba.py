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
"""
NJIT = dict(cache=True, fastmath=False)
NJIT_DEM = dict(cache=True, fastmath={"contract"}, error_model="numpy")
NJIT_DEM_INLINE = dict(NJIT_DEM, inline="always")
