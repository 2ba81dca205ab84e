"""Why a claim of P1 does not hold on the campaign's data: `EXPLANATIONS` gives, per claim (and system where the
cause differs), the cause and its basis — the command that measured it, or none when the cause is a hypothesis
(`forcenet.report.claims.Explanation`). The numbers quoted are those of `config/validation.yaml`'s campaign
(docs/validation/p1.md); docs/validation/README.md gives the longer account.
"""
from __future__ import annotations

from forcenet.report.claims import Explanation

# The commands that measured a cause (the basis column of the table); a cause without one is a hypothesis.
SURVEY = "python scripts/p1_network_survey.py --results results/validation"
PER_REALIZATION = ("python scripts/damping_series.py results/validation:2d_linear:0 … results/validation:2d_hertz:4 "
                   "results/validation:3d_hertz:0 … :2 (docs/validation/damping.md)")
CONTACT_NUMBER_RUN = ("python scripts/damping_series.py results/validation:2d_linear_contacts "
                      "results/validation:2d_hertz_contacts results/validation:2d_linear:0 … :4 "
                      "results/validation:2d_hertz:0 … :4 results/validation:2d_linear_strict "
                      "results/validation:2d_hertz_strict")
FRICTIONLESS_3D = "python scripts/p1_network_survey.py --results results/validation --systems 3d_hertz 3d_hertz_mu0"
OVERLAPS = "python scripts/overlap_survey.py --system 2d_linear 2d_hertz 3d_hertz"
TABLE = "snakemake validation_report --configfile config/validation.yaml (the row's reading beside, docs/validation/p1.md)"
DAMPING_CONTROL = ("python scripts/judge_records.py --systems 2d_linear_lightdamp 2d_hertz --resamples 100, the same "
                   "with 2d_linear_literal (docs/validation/controls.md, 'Reading of (a)', 'Reading of (b)')")
HYPOTHESIS_ONLY = ""
CAMPAIGN_PREFIX = "At the papers' sizes (config/validation.yaml, docs/validation/p1.md): "

_ONE_STEP = ("The jamming transition is crossed within one rho step in every run (Z without rattlers 0.87 -> 4.18 "
             "from rho 0.58 to 0.59 in 3D, 1.09 -> 3.42 from 0.81 to 0.82 in 2D Hertz, 1.64 -> 3.32 from 0.80 to "
             "0.81 in 2D linear), so no state lies inside the transition where P1 places this feature.")
# control (a) of docs/validation/controls.md: the linear law damped as lightly as the Hertz law near jamming
_DAMPING_ARTEFACT = (" A damping artefact of this reproduction (docs/validation/controls.md, reading fixed before "
                     "its runs): with the linear law damped as lightly as the Hertz law near jamming (e_n 0.992, "
                     "2d_linear_lightdamp, 4 runs) {holds}; P1's own relation for gamma_n taken literally for the "
                     "linear law (e_n 0.640, 2d_linear_literal, 5 runs) gives the shipped miss ({literal}). The "
                     "lightly damped runs keep no contacts below rho_J and fail P1's "
                     "below-jamming claims (clusters, Z and phi_c at rho_J, B1 = 0 below): none of e_n 0.5, 0.640, "
                     "0.992 of the linear law meets both in the 50 x 50 box.")
_SHORT_PATHS = ("Our clusters are open paths, but short ones: for a tree S_p = 1 - clusters/particles exactly, so "
                "S_p 0.55-0.7 means 2-3 particles per cluster; S_p ~ 1 needs paths of ten or more.")

#: claim id, or (claim id, system) where the cause is the system's own -> (cause, command or HYPOTHESIS_ONLY)
EXPLANATIONS: dict[str | tuple[str, str], tuple[str, str]] = {
    ("p1-1-b0-maximum-above-mean-force", "3d_hertz"): (
        "The B0 maximum follows the threshold where the spanning network breaks up: beyond jamming the majority "
        "percolates up to F_th 1.6-1.65 <F> in 3D (from rho = 0.61 on) against 1.1-1.3 in 2D, the 3D force network holding more "
        "large forces (its PDF is the widest, p1-5.3-pdf-wider-nonlinear), so its B0 maximum lies at 1.8 <F>.",
        SURVEY),
    "p1-3-overlap": (
        "The largest overlap sits at a particle pressed by a wall in 11 of the 13 last states (the corner and wall "
        "disks the grid stops were set by); away from the walls it is 0.10-0.15, and 99 % of the contacts "
        "overlap by at most 7.3-8.8 % (median 3-4 %), within P1's 10 %.", OVERLAPS),
    "p1-3-relaxation": (
        "The verdicts mostly stay (72 of 79 the same on the four pairs) but the contact-number runs move rho_J "
        "by a grid step, in opposite directions. Both relaxed every unjammed state to the 3e6-step cap (their "
        "few contacts keep changing). 2d_linear_contacts (Z 0.002-0.36 below jamming) jams at 0.817 against "
        "0.8066-0.8073 over 2d_linear's five realizations (+0.010); 2d_hertz_contacts (Z 0.012-0.20) jams at "
        "0.808 against 0.8167-0.8183 over 2d_hertz's five (-0.009; Z 2.72 at rho 0.81, where 2d_hertz's five "
        "have 0.13-0.29): each twice the half step allowed. The stricter-tolerance runs move it by +0.0004 and +0.0012.",
        CONTACT_NUMBER_RUN),
    "p1-4.1-pdf-order-at-rho-max": (
        "Our linear rho_max under the F_max rule is 0.82, one step after its rho_J, where its force PDF is still "
        "wide; at P1's printed rho_max the order holds (p1-4.1-pdf-order-at-paper-rho-max).", TABLE),
    ("p1-4.2-cluster-size-peak-threshold", "3d_hertz"): (
        "<S>/N peaks where the last spanning cluster breaks up, and in 3D that threshold falls after jamming: "
        "2.3 <F> at the first jammed state (0.59), 1.75 at 0.60 and 1.55-1.7 from 0.61 on; the judge sees that "
        "plateau (median 1.65), 0.35 below P1's ~2.0.", SURVEY),
    "p1-4.3-percolating-small-3d-near-jamming": (
        _ONE_STEP + " The first jammed 3D state already percolates with 75 % of the particles.", SURVEY),
    ("p1-4.3-contact-number-at-jamming", "3d_hertz"): (
        "P1's ~6 is the frictionless value: at its first jammed state the mu = 0 run (3d_hertz_mu0, one "
        "realization, rho_J 0.617) has rattler-free Z 5.74 (6.17 one step later), our mu = 0.5 runs 4.18 (4.80), "
        "reaching 6 only at rho = 0.66. Z at rho_J itself interpolates across the one-step jump of Z (4.47 with "
        "friction, 4.36 without).", FRICTIONLESS_3D),
    ("p1-4.3-phi-c-at-jamming", "3d_hertz"): (
        "phi_c = 1/(Z - 1) follows Z at rho_J (p1-4.3-contact-number-at-jamming): at the first jammed state it is "
        "0.21 without friction (3d_hertz_mu0, Z 5.74), P1's ~0.2, and 0.31 with mu = 0.5 (Z 4.18).",
        FRICTIONLESS_3D),
    ("p1-5.1-b0-ridge", "3d_hertz"): (_ONE_STEP, SURVEY),
    "p1-5.1-b0-ridge-law-contrast": (
        "The ridge exists in 2D Hertz but is 1.19x the linear law's, not 2x: per realization the B0/N at "
        "F_th < 0.5 within 0.02 of rho_J is 0.0040-0.0153 (Hertz) and 0.0059-0.0138 (linear), a spread within "
        "one law larger than the difference between the laws, and the single runs of the damping series (0.004-0.025 "
        "over gamma_n 1.386-31.37) lie in the same range. In P1's 75 x 75 size-check box the laws separate: 5 runs "
        "each give 0.019-0.033 (Hertz) against 0.007-0.015, no overlap, and this judge's ratio 2.60, robustness "
        "0.84, the Hertz packings keeping 133-1235 particles with >= 2 contacts just below rho_J (25-143 at 50 x 50)."
        + _DAMPING_ARTEFACT.format(holds="the ratio is 23.7, robustness 1.00, the linear ridge falling to 0.00037",
                                   literal="ratio 1.14, robustness 0"),
        PER_REALIZATION + "; the 75 x 75 runs: python scripts/p1_subset_table.py --results results/validation "
        "--systems 2d_linear_box75 2d_hertz_box75 --realizations 5 "
        "(docs/validation/README.md, 'The current reading: P1'); " + DAMPING_CONTROL),
    ("p1-5.1-b1-zero-below", "3d_hertz"): (
        "rho_J = 0.595 (inflection of Z) falls between 0.59 and 0.60 and the state at 0.59 is already jammed "
        "(rattler-free Z 4.18, percolating): its loops count as below jamming. With the cut one tolerance under "
        "rho_J (the reading beside) the claim holds.", SURVEY),
    "p1-5.2-shape-open-paths-below-jamming": (_SHORT_PATHS, SURVEY),
    "p1-5.2-shape-open-paths-large-threshold": (_SHORT_PATHS, SURVEY),
    "p1-5.2-shape-linear-above-hertz": (
        "At equal rho beyond both rho_J the two 2D laws differ in S_p by +0.03..+0.05 at F_th = 0.5, -0.02..-0.03 "
        "at 1.0 and -0.05 at 1.5 (mean -0.01), following the share of contacts each keeps at F >= F_th: the "
        "linear PDF is narrower, so it keeps more contacts at 0.5 <F> and fewer at 1.5 <F>; P1's 'significantly "
        "more complex' needs markedly more around <F>.", SURVEY),
    "p1-5.2-shape-linear-above-3d": (
        "With one spanning cluster S_p is about half the rattler-free Z: 3D Z 4.8-6.7 against 3.3-4.2 for the "
        "linear law, so 3D S_p (1.37-1.70 at <F>) lies above the linear one (1.09-1.19).", SURVEY),
    "p1-5.2-shape-noisier-in-3d": (
        "Pooled over the clusters, S_p beyond jamming at F_th < 1 is that of the spanning cluster, which has more "
        "edges in 3D and so spreads less; P1's 'few clusters' noise is that of the mean over clusters, under "
        "which the claim holds (the reading beside).", TABLE),
    "p1-5.3-rough-fewer-nonlinear": (
        "At the rho both 2D laws sampled beyond their rho_J (0.84-0.88) their rough-bin N0/N cross (Hertz minus "
        "linear +0.0023, +0.0010, -0.0010, -0.0002, +0.0019 around 0.042-0.048): the 4 % excess of the Hertz mean "
        "comes from its further states (0.89-0.91: 0.047-0.049), which the linear grid does not reach. 3D has "
        "fewer (0.030-0.035)."
        + _DAMPING_ARTEFACT.format(holds="the Hertz/linear ratio is 0.933, robustness 0.97",
                                   literal="1.055, robustness 0.03"),
        SURVEY + "; " + DAMPING_CONTROL),
    ("p1-5.3-strong-peak-linear-only", "2d_hertz"): (
        "The strong bin counts the components born at F >= 2.5 <F>, and their number follows the contacts that "
        "strong: the force PDF is widest at the first jammed state and their share halves within 0.02 in both 2D "
        "laws (Hertz 0.030 -> 0.015, linear 0.021 -> 0.010), so both strong-bin curves peak there and fall "
        "(Hertz 0.0223 -> 0.0157, linear 0.0182 -> 0.0115). Beyond, the Hertz curve stays 1.3-1.4x the linear "
        "one (0.014-0.015 against 0.010-0.011 at 0.85-0.88); in 3D, where Z keeps rising (4.8 -> 6.7), it grows "
        "again after the first jammed state (0.041 -> 0.056).", SURVEY),
    "p1-5.3-weak-peak-nonlinear-only": (
        "Per realization the weak-bin N0/N within 0.02 of rho_J is 0.0035-0.0099 (Hertz) and 0.0040-0.0084 "
        "(linear): the two laws overlap, and on one scale the linear peak is the larger."
        + _DAMPING_ARTEFACT.format(holds="the prominences differ by 0.404 (0.596 against 0.192), robustness 0.83",
                                   literal="0.058, robustness 0"),
        PER_REALIZATION + "; " + DAMPING_CONTROL),
    "p1-5.3-tp0-steeper-in-3d": (
        "TP0/N rises in one rho step in every system (2D linear 0.005 -> 0.061, 2D Hertz 0.001 -> 0.064, 3D "
        "0.0003 -> 0.074), so the rise compares the heights of the steps: 3D's is 1.33x the 2D ones, the judge asks "
        "1.5x. What would make P1's 3D rise much larger is not measured.", SURVEY),
    ("p1-6-cluster-size-peak-small-threshold", "2d_linear"): (
        "The linear law keeps more contacts below jamming (rattler-free Z 1.64 at 0.80 against 0.70-1.09 for "
        "Hertz at 0.80-0.81), so its <S>/N at F_th ~ 0 near rho_J is the larger (0.0045-0.0098 per realization "
        "against 0.0015-0.0025)."
        + _DAMPING_ARTEFACT.format(holds="the peak is absent (relative prominence 0.108), robustness 1.00",
                                   literal="present, relative prominence 0.446, robustness 0.16"),
        PER_REALIZATION + "; " + DAMPING_CONTROL),
    ("p1-6-cluster-size-peak-small-threshold", "3d_hertz"): (
        _ONE_STEP + " The last unjammed 3D state holds few clusters (<S>/N at F_th ~ 0 0.0006-0.0008 per "
                    "realization).", PER_REALIZATION),
}


def explain(claim_id: str, system: str) -> Explanation | None:
    """Why claim `claim_id` does not hold for `system` ("all" for a claim across systems): the system's own cause,
    else the claim's, else None (no cause recorded)."""
    cause = EXPLANATIONS.get((claim_id, system)) or EXPLANATIONS.get(claim_id)
    if not cause:
        return None
    text, command = cause
    # the numbers are the paper-size campaign's: said so, since the quick build's table shows the same text
    return Explanation(f"{CAMPAIGN_PREFIX}{text}", command)
