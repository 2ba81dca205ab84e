"""numba kernels of the DEM engine, one module per concept; the drivers are `forcenet.dem.engine` (state, named
tuples of arguments, neighbour-list rebuilds) and `forcenet.dem.protocol` (compressions).

* `law`: the contact law of P1 Eq. 1–3, once per dimension, and the head-on collision that calibrates γ_n;
* `contacts`: the pair loops and the flat walls, each used by the time step and to record a snapshot;
* `gear`: the Gear predictor–corrector;
* `neighbours`: cell list, Verlet list, springs carried across a rebuild;
* `stepping`: `advance`, the time-step loop, with the wall motion and the checks that stop it.

Only numpy, numba and math are imported (plus the DEM numba options, `forcenet._numba.NJIT_DEM`, and each other).
Everything is in reduced units: length d_ave, mass m̄, time τ_c.
"""
