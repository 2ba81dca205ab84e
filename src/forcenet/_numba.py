"""The one place for numba compilation options (STYLE.md): every kernel is `@numba.njit(**NJIT)`.

`fastmath` stays off: it would let LLVM assume no NaN/inf, which breaks the DEM's blow-up checks and
makes results depend on reassociation.
"""
NJIT = dict(cache=True, fastmath=False)
