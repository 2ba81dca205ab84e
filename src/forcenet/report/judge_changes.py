"""The judges changed after their verdicts had been read (issue 53, the referee's fixes), each with the rule it now
applies and the verdict each row had under the old judge, read from the committed campaign tables of that day
(``docs/validation/p1.csv`` generated 2026-11-26, ``p2.csv`` 2026-11-27). The tables show them in the column
``judge_changed_after_reading`` (`forcenet.report.claims.JudgeChange`), so that a reader sees which rows changed
judge after their verdicts were known. A rule is written once here and judged in `forcenet.report.p1_claims`,
`p1_claims_topology`, `p1_judging`, `p2_claims` and `p2_claims_friction`.
"""
from __future__ import annotations

from forcenet.report.claims import JudgeChange

BELOW_JUMP = ("below jamming = the states up to the last one before the jump of the mean Z, never at or above rho_J "
              "(was every state with rho < rho_J)")
MARGIN = "its judge gives a margin, so a verdict near its threshold is marked marginal (it gave none)"
ONE_RUN = ("the verdict rests on one run of each counterpart, and its robustness says so (was a share over the "
           "resamples of P1's own systems alone)")

_HOLDS, _FAILS, _MARGINAL = "holds", "does not hold", ", marginal"


def _same(verdict: str, *systems: str) -> dict[str, str]:
    """{system: verdict} for `systems` all with one verdict."""
    return {system: verdict for system in systems}


_2D = ("2d_hertz", "2d_linear")
_ALL3 = ("2d_hertz", "2d_linear", "3d_hertz")

#: P1's claims whose judge changed after the verdicts of docs/validation/p1.md (2026-11-26) were read
P1_CHANGES: dict[str, JudgeChange] = {
    # "below jamming" (P1 §3, §5): the jump of Z, not the inflection point, separates the states
    "p1-3-clusters-below-jamming": JudgeChange(BELOW_JUMP, _same(_HOLDS, *_2D)),
    "p1-5.1-b1-zero-below": JudgeChange(BELOW_JUMP, {"2d_hertz": _HOLDS, "2d_linear": _HOLDS, "3d_hertz": _FAILS}),
    "p1-5.1-b2-zero-below": JudgeChange(BELOW_JUMP, {"3d_hertz": _HOLDS}),
    "p1-5.3-tp2-zero-below": JudgeChange(BELOW_JUMP, {"3d_hertz": _HOLDS}),
    "p1-6-pdf-2d-3d-differ-below-jamming": JudgeChange(BELOW_JUMP, {"all": _HOLDS + _MARGINAL}),
    "p1-5.2-shape-open-paths-below-jamming": JudgeChange(BELOW_JUMP, _same(_FAILS, *_2D)),
    "p1-5.2-shape-linear-above-hertz-below-jamming": JudgeChange(BELOW_JUMP, {"all": _HOLDS}),
    "p1-5.3-medium-jump": JudgeChange(
        "the jump measured from the last state before the jump of Z (was the last rho < rho_J - tol); " + MARGIN,
        _same(_HOLDS, *_ALL3)),
    "p1-5.1-b1-rises": JudgeChange(
        "the rise measured from the last state before the jump of Z (was the last rho <= rho_J); " + MARGIN,
        _same(_HOLDS, *_ALL3)),
    # P1 §4.1's one sentence, once
    "p1-4.1-pdf-order-at-rho-max": JudgeChange(
        "P1's sentence judged once, at P1's printed rho_max, the order at our rho_max beside in the evidence (was two "
        "rows)", {"all": "does not hold, marginal at our rho_max; p1-4.1-pdf-order-at-paper-rho-max: holds, "
                         "marginal"}),
    # P1 §3's overlaps at P1's own depth above jamming
    "p1-3-overlap": JudgeChange(
        "judged at P1's own depth above jamming, rho_J + 0.056, within one grid step (was at our largest rho)",
        _same(_FAILS, *_ALL3)),
    # judges that gave no margin
    "p1-4-percolation-at-jamming": JudgeChange(MARGIN, _same(_HOLDS, *_ALL3)),
    "p1-5.3-pdf-wider-nonlinear": JudgeChange(MARGIN, {"all": _HOLDS}),
    "p1-4.2-cluster-size-peak-threshold": JudgeChange(
        MARGIN, {"2d_hertz": _HOLDS, "2d_linear": _HOLDS, "3d_hertz": _FAILS}),
    "p1-4.2-cluster-size-decays-faster-linear": JudgeChange(MARGIN, {"all": _HOLDS}),
    "p1-4.2-cluster-size-3d-larger-forces": JudgeChange(MARGIN, {"all": _HOLDS}),
    "p1-4.3-percolating-almost-all-2d": JudgeChange(MARGIN, _same(_HOLDS, *_2D)),
    "p1-4.3-percolating-significant-2d": JudgeChange(MARGIN, _same(_HOLDS, *_2D)),
    "p1-4.3-percolating-small-3d-near-jamming": JudgeChange(MARGIN, {"3d_hertz": _FAILS}),
    "p1-4.3-percolating-small-3d-large-threshold": JudgeChange(MARGIN, {"3d_hertz": _HOLDS}),
    "p1-4.3-percolating-smaller-in-3d": JudgeChange(MARGIN, {"all": _HOLDS}),
    "p1-4.3-phi-c-lower-bound": JudgeChange(MARGIN, _same(_HOLDS, *_ALL3)),
    "p1-5.1-b0-interior-maximum": JudgeChange(MARGIN, _same(_HOLDS, *_ALL3)),
    "p1-5.1-b1-plateau": JudgeChange(MARGIN, {"2d_hertz": _HOLDS, "2d_linear": "not evaluated", "3d_hertz": _HOLDS}),
    "p1-5.1-b1-larger-in-3d": JudgeChange(MARGIN, {"all": _HOLDS}),
    "p1-5.2-shape-open-paths-large-threshold": JudgeChange(MARGIN, _same(_FAILS, *_ALL3)),
    "p1-5.2-shape-linear-above-hertz": JudgeChange(MARGIN, {"all": _FAILS}),
    "p1-5.2-shape-3d-above-2d-hertz": JudgeChange(MARGIN, {"all": _HOLDS}),
    "p1-5.2-shape-linear-above-3d": JudgeChange(MARGIN, {"all": _FAILS}),
    "p1-5.2-shape-noisier-in-3d": JudgeChange(MARGIN, {"all": _FAILS}),
    "p1-5.2-shape-bounds": JudgeChange(MARGIN, _same(_HOLDS, *_ALL3)),
    "p1-5.3-rough-similar-near-jamming": JudgeChange(MARGIN, {"all": _HOLDS}),
    "p1-5.3-rough-fewer-nonlinear": JudgeChange(MARGIN, {"all": _FAILS}),
    "p1-5.3-medium-fewer-nonlinear": JudgeChange(MARGIN, {"all": _HOLDS}),
    "p1-5.3-linear-medium-over-strong": JudgeChange(MARGIN, {"2d_linear": _HOLDS}),
    "p1-5.3-weak-peak-at-ridge": JudgeChange(MARGIN, {"2d_hertz": _HOLDS, "3d_hertz": "not evaluated"}),
    "p1-5.3-tp0-steeper-in-3d": JudgeChange(MARGIN, {"all": _FAILS}),
    "p1-5.3-tp1-steeper-in-3d": JudgeChange(MARGIN, {"all": _HOLDS}),
    # verdicts that rest on one run of a counterpart
    "p1-3-system-size": JudgeChange(ONE_RUN, {"all": _HOLDS + ", robustness 1"}),
    "p1-3-system-size-3d": JudgeChange(ONE_RUN, {"all": "not evaluated"}),
    "p1-3-friction": JudgeChange(ONE_RUN, {"all": _HOLDS + _MARGINAL + ", robustness 1"}),
    "p1-3-relaxation": JudgeChange(ONE_RUN, {"all": _FAILS + ", robustness 0"}),
    # φ_c at the first jammed state beside the interpolated value
    "p1-4.3-phi-c-at-jamming": JudgeChange(
        "phi_c at the first jammed state (after the jump of Z) in the evidence beside the value interpolated at rho_J; "
        "the verdict's rule is unchanged", {"2d_hertz": _HOLDS, "2d_linear": _HOLDS, "3d_hertz": _FAILS}),
    # the 3D B0 maximum against P1's own 3D statement
    "p1-1-b0-maximum-above-mean-force": JudgeChange(
        "3D judged against P1's own 3D statement, F_th ~ 2.0 within 0.25 (was (1, 1.5] <F> as in 2D)",
        {"3d_hertz": _FAILS}, systems=("3d_hertz",)),
}

_TABLES = "2d_poly_mu05 (one realization)"
_TABLES_ONE_RUN = "Tables I-III rest on one realization, and the robustness says so (it showed none)"

#: P2's claims whose judge changed after the verdicts of docs/validation/p2.md (2026-11-27) were read
P2_CHANGES: dict[str, JudgeChange] = {
    "III.D-1": JudgeChange(_TABLES_ONE_RUN, {_TABLES: _FAILS}),
    "III.D-2": JudgeChange(
        "its margin is measured against P2's own Table I quotients (beta0 1.88, beta1 2.91: how far ours lies from 1 "
        "relative to how far P2's does; was relative to 1 alone); " + _TABLES_ONE_RUN, {_TABLES: _HOLDS}),
    "III.D-3": JudgeChange(_TABLES_ONE_RUN, {_TABLES: _HOLDS}),
    "III.D-4": JudgeChange(
        "its margin is measured against P2's own Table III ratio (median largest/smallest quadrant 1.46: how far ours "
        "lies from the limit relative to how far P2's does; was relative to the limit alone); " + _TABLES_ONE_RUN,
        {_TABLES: _HOLDS}),
    "IV.C-4": JudgeChange(
        "marginal when the lead lies within two sampling steps (it is the difference of two maxima, each on the "
        "sampling grid; was one step)", {"": _FAILS + ", robustness 0.42"}),
    "IV.C-8a": JudgeChange(
        "IV.C-8 split into the regimes below and above both rho_J (was one row over every state)",
        {"": "IV.C-8: does not hold, median PD1 points over every state 1.02 (mu = 0) against 7.22"}),
    "IV.C-8b": JudgeChange(
        "IV.C-8 split into the regimes below and above both rho_J (was one row over every state)",
        {"": "IV.C-8: does not hold, median PD1 points over every state 1.02 (mu = 0) against 7.22"}),
}
