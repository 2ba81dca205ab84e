"""The claims framework of both papers' validation tables (P1: `forcenet.report.p1_validation`, P2:
`forcenet.report.p2_validation`).

A **claim** (`Claim`) is one statement a paper makes about its results: an id, the paper's section, the statement,
the paper's value (a number, per system role or one for all, or the paper's words), the criterion it is judged by
(text with the tolerances of the one record both papers share, `ClaimTolerances`, filled in) and the function
that judges it. Judging it on our data gives a `Judgement` (our key number, the evidence, holds or not, how far the
deciding number lies from its threshold, whether it holds only on zeros, the states that carry it) or raises
`NotEvaluated` (the data cannot decide: a system, a ρ range, a quantity is missing; the message says which). A
judged claim (`JudgedClaim`) is one row of a validation table, the same record for both papers: id, section,
statement, system, paper value, criterion, our value (a number), evidence (text), verdict (`HOLDS`, `FAILS`,
`NOT_EVALUATED`), marker (`MARGINAL`, `VACUOUS`), states, robustness (the share of bootstrap resamples of the
realizations under which it holds, `holds_share`), reading (another reading set beside, `rows_beside`) and, where
a paper records one, why it does not hold and on what basis (`Explanation`: measured with a command, or a
hypothesis). `verdict_counts` counts the fair, marginal and vacuous verdicts apart.

The tables themselves (columns, CSV and Markdown, the paper-size column, comparing two tables) are
`forcenet.report.claims_table`.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, is_dataclass
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pandas as pd

from forcenet.boxes import P1_OVERLAP_BOUND

__all__ = ["HOLDS", "FAILS", "NOT_EVALUATED", "IMPORTED_NOT_EVALUATED", "MARGINAL", "VACUOUS", "MARGINAL_FRACTION",
           "MEASURED", "HYPOTHESIS", "BELOW_BEFORE_JUMP", "BELOW_TOLERANCE", "ClaimTolerances", "NotEvaluated",
           "Judgement", "relative_margin", "contrast_margin", "smallest_margin", "ratio_margin", "reference_margin",
           "Claim", "claim_register", "Explanation", "JUDGE_CHANGE_DATE", "JudgeChange", "JudgedClaim",
           "holds_share", "one_run_text", "judge_claim", "rows_beside", "verdict_counts", "verdict_summary"]

HOLDS, FAILS, NOT_EVALUATED = "holds", "does not hold", "not evaluated"

#: why a claim about the papers' compression protocol is not judged on imported states (`forcenet.importers`)
IMPORTED_NOT_EVALUATED = ("imported states: the claim is about the paper's compression protocol (walls, speed, "
                          "relaxation, sampling through jamming), which an import does not record")


class NotEvaluated(Exception):
    """Raised by a judge when the claim cannot be judged from the data; the message says why."""


MARGINAL, VACUOUS = "marginal", "vacuous"  # markers set beside a verdict (issue 25)
MARGINAL_FRACTION = 0.10  # a verdict decided within 10 % of its threshold is marginal (issue 25)
MEASURED, HYPOTHESIS = "measured", "hypothesis"  # the basis of an explanation of a verdict


#: the two cuts of "below jamming": the states before the jump of the mean Z, up to the last unjammed state (never
#: at or above the inflection point ρ_J; the table's cut), and the older cut one tolerance under ρ_J (judged beside)
BELOW_BEFORE_JUMP, BELOW_TOLERANCE = "rho up to the last state before the jump of Z", "rho < rho_J - tol"


@dataclass(frozen=True)
class ClaimTolerances:
    """The one tolerance record of both papers' claims: how their words are turned into tests. Every verdict uses
    these and nothing else. P1's fields are keyword arguments of `forcenet.report.p1_validation.p1_validation`;
    the record is the ``tolerances`` argument of `forcenet.report.p2_validation.p2_validation`.

    P1 (§3–6):

    rho_tolerance : "near ρ_J" means |ρ − ρ_J| ≤ this; "beyond ρ_J" means ρ > ρ_J + this.
        None: the larger of P1's Δρ = 0.02 and the system's own ρ step.
    below_cut : which states are "below jamming": `BELOW_BEFORE_JUMP` (the states up to the last one before the
        largest rise of the mean Z between two consecutive states, never at or above ρ_J; the table's cut) or
        `BELOW_TOLERANCE` (ρ < ρ_J − rho_tolerance; judged beside it).
    rho_window : width of the ρ window of "a rise close to ρ_J" (ρ_J ± this) and of "a plateau near ρ_max"
        (the last window before ρ_max). None: twice the system's rho_tolerance.
    min_prominence : a peak of a curve versus ρ needs a topographic prominence ≥ this fraction of its scale
        (B0/N ridge and ⟨S⟩/N peak: the largest value over (ρ, F_th); persistence bins: the curve's maximum).
    negligible_fraction : "B_k = 0", "TP2 ≈ 0": the largest value below ρ_J ≤ this fraction of the largest
        value of the curve; a rise is real when it exceeds this fraction of the maximum.
    monotone_tolerance : "grows monotonically": no drop between consecutive ρ beyond ρ_J larger than this
        fraction of the curve's maximum.
    plateau_fraction : "plateaus near ρ_max": the change over the last `rho_window` before ρ_max ≤ this
        fraction of the whole rise up to ρ_max.
    threshold_tolerance : an F_th P1 quotes (1.25, 1.5, 2.0) is met within this (P1 quotes multiples of 0.25).
    unity_tolerance : "S_p ≈ 1": |median S_p − 1| ≤ this.
    shape_difference : "S_p significantly larger": the means differ by at least this.
    almost_all : "almost all the particles" in the percolating cluster: median N_per/N ≥ this.
    small_share : "a very small number of particles" in the percolating cluster: N_per/N ≤ this (P1's own
        estimate φ_c ≈ 0.2 in 3D sets the scale).
    similar_ratio : "very similar" across systems: largest / smallest ≤ this.
    jump_factor : "a sudden increase beyond jamming": the value at the first ρ beyond ρ_J ≥ this × the value at
        the last ρ below it.
    steeper_factor : "a significantly more prominent increase close to ρ_J" in 3D: its rise over ρ_J ±
        rho_window ≥ this × the larger 2D rise.
    pdf_distance : "significantly different" force PDFs: total-variation distance ½ ∫|p − q| dF ≥ this.
    min_clusters : "a non-vanishing number of clusters": realization-mean count per snapshot ≥ this.
    contrast_factor : "pronounced" for one law, "rather insignificant" for the other (P1 §5.1, §5.3): the
        prominence of one law's peak ≥ this × the other's, on one scale.
    approx_fraction : "⟨k⟩ ≈ 3", "φ_c ≈ 0.5" (P1 §4.3): within this fraction of P1's value.
    same_verdicts : "qualitatively the same" (P1 §3: other sizes, friction): this share of the per-system claims
        judged on both runs has the same verdict.
    overlap_bound : P1 §3's "overlaps up to 10 % of the sum of the radii" at the largest ρ, judged at P1's own
        depth above jamming (`overlap_depth`) within one grid step.
    overlap_depth : how far above ρ_J P1's largest ρ lies: None, the smallest of P1's ρ_max − ρ_J (0.890 − 0.834
        = 0.056, 2D linear), the depth P1 reaches in every system.
    rho_j_shift : P1 §3's stricter relaxation "does not change the measured quantities significantly": ρ_J of the
        run relaxed more strictly within this of the system's. None: half the system's ρ step, the resolution of
        the grid the inflection of Z is fitted on.

    P2 (§III D–§V): documented field by field below.
    """

    rho_tolerance: float | None = None
    rho_window: float | None = None
    min_prominence: float = 0.2
    negligible_fraction: float = 0.05
    monotone_tolerance: float = 0.1
    plateau_fraction: float = 0.25
    threshold_tolerance: float = 0.25
    unity_tolerance: float = 0.25
    shape_difference: float = 0.1
    almost_all: float = 0.8
    small_share: float = 0.3
    similar_ratio: float = 1.5
    jump_factor: float = 2.0
    steeper_factor: float = 1.5
    pdf_distance: float = 0.1
    min_clusters: float = 1.0
    contrast_factor: float = 2.0
    approx_fraction: float = 0.15
    same_verdicts: float = 0.8
    overlap_bound: float = P1_OVERLAP_BOUND
    overlap_depth: float | None = None
    rho_j_shift: float | None = None
    below_cut: str = BELOW_BEFORE_JUMP
    # --- P2 ---
    value_factor: float = 1.5  # "≈ x", "roughly the same", "similar": measured within [x / f, x · f]
    max_cv: float = 0.5  # "roughly / essentially constant": coefficient of variation over the ρ range ≤ this
    fall_factor: float = 10.0  # "slows dramatically" after ρ_J: median after ≤ median just before / this (ours)
    rate_window: float = 0.05  # "just before jamming": the rates over [ρ_J − this, ρ_J) (IV.A-11)
    drop_factor: float = 2.0  # "decreases dramatically" / "plunges" inside the unjammed regime
    decades: float = 0.5  # "n orders of magnitude smaller": measured log10 drop within n ± this
    trend: float = 0.5  # "increases" / "decreases" with ρ: Spearman rank correlation ≥ this / ≤ −this
    correlation: float = 0.7  # "tracks" / "follows": Pearson correlation of the log10 curves ≥ this
    near_jamming: float = 0.02  # "near / close to ρ_J": |ρ − ρ_J| ≤ this
    peak_window: float = 0.03  # "at ρ ≈ x" for an extremum: it lies within x ± this
    well_below: float = 0.05  # "ρ significantly less than ρ_J": ρ < ρ_J − this
    consistently: float = 0.8  # "consistently larger": true at this fraction of the compared ρ values
    dominance: float = 2.0  # "concentrated in one quadrant": largest ≥ this × second largest (median over columns)
    spread: float = 2.0  # "distributed evenly": largest / smallest quadrant ≤ this (median over columns)
    min_points: int = 2  # fewer ρ values than this in a range: the claim is not evaluated
    correlation_points: int = 3  # fewer ρ values than this: no correlation is computed (2 points always give ±1)

    def __post_init__(self):
        """Refuse an unknown cut of "below jamming"."""
        if self.below_cut not in (BELOW_BEFORE_JUMP, BELOW_TOLERANCE):
            raise ValueError(f"below_cut must be {BELOW_BEFORE_JUMP!r} or {BELOW_TOLERANCE!r}, not {self.below_cut!r}")


@dataclass(frozen=True)
class Judgement:
    """What a judge found: the key number (NaN where the evidence is the whole answer), the evidence (the numbers
    behind the verdict, as text) and whether the claim holds.

    margin : how far the deciding number lies from its threshold, relative to the threshold (`relative_margin`,
        `contrast_margin`); NaN where the judge has no single threshold. A verdict with margin ≤
        `MARGINAL_FRACTION` is marked `MARGINAL`.
    grid_step : the verdict turns if one state moves by one grid step (a peak or a cut one ρ step from its
        boundary): marked `MARGINAL` as well.
    vacuous : the claim holds only because its quantity is zero everywhere it is judged (nothing to contrast):
        marked `VACUOUS` instead of a plain "holds".
    states : the states (ρ) that carry the verdict, as text ("" where the evidence says it).
    one_run : the systems with a single run (realization) that the verdict rests on (P1 §3's counterparts): no
        resample varies them, so the row says so in its robustness (`one_run_text`).
    """

    measured: float
    evidence: str
    holds: bool
    margin: float = math.nan
    grid_step: bool = False
    vacuous: bool = False
    states: str = ""
    one_run: tuple[str, ...] = ()

    @property
    def marker(self) -> str:
        """`VACUOUS` for a vacuous pass, `MARGINAL` for a verdict within `MARGINAL_FRACTION` of its threshold or
        one grid step from turning, else ""."""
        if self.vacuous and self.holds:
            return VACUOUS
        if self.grid_step or (np.isfinite(self.margin) and self.margin <= MARGINAL_FRACTION):
            return MARGINAL
        return ""


def relative_margin(value: float, threshold: float) -> float:
    """|value − threshold| / |threshold|: how far a number lies from the threshold it is compared with (inf for
    a threshold of 0 and a nonzero value, 0 when both are 0, NaN when either is not finite)."""
    value, threshold = float(value), float(threshold)
    if not (np.isfinite(value) and np.isfinite(threshold)):
        return math.nan
    if threshold == 0:
        return 0.0 if value == 0 else math.inf
    return abs(value - threshold) / abs(threshold)


def contrast_margin(first: float, second: float) -> float:
    """|first − second| / max(|first|, |second|): how far two numbers compared with each other ("a > b") lie
    apart, relative to the larger (0 when both are 0, NaN when either is not finite)."""
    first, second = float(first), float(second)
    if not (np.isfinite(first) and np.isfinite(second)):
        return math.nan
    scale = max(abs(first), abs(second))
    return abs(first - second) / scale if scale > 0 else 0.0


def smallest_margin(*margins: float) -> float:
    """The smallest finite margin of several thresholds one verdict rests on (NaN when none is finite)."""
    finite = [float(m) for m in margins if np.isfinite(m)]
    return min(finite) if finite else math.nan


def ratio_margin(ratio: float, factor: float) -> float:
    """How far a ratio lies from the factor it must reach or stay within, on a log scale relative to the factor's
    own log: |log ratio − log factor| / |log factor| (inf for a ratio of 0 or inf, infinitely far on that scale;
    NaN for a ratio of NaN or a factor that is not positive and finite, or 1)."""
    ratio, factor = float(ratio), float(factor)
    if not (np.isfinite(factor) and factor > 0 and factor != 1) or math.isnan(ratio) or ratio < 0:
        return math.nan
    if ratio == 0 or math.isinf(ratio):
        return math.inf
    return abs(math.log(ratio) - math.log(factor)) / abs(math.log(factor))


def reference_margin(value: float, threshold: float, reference: float) -> float:
    """How far `value` lies from `threshold` relative to how far the paper's own `reference` value lies from it,
    on a log scale: |log(value / threshold)| / |log(reference / threshold)| (1: as far as the paper's; NaN unless
    all three are positive and finite and the reference differs from the threshold)."""
    value, threshold, reference = float(value), float(threshold), float(reference)
    if not all(np.isfinite(x) and x > 0 for x in (value, threshold, reference)) or reference == threshold:
        return math.nan
    return abs(math.log(value / threshold)) / abs(math.log(reference / threshold))


@dataclass(frozen=True)
class Claim:
    """One claim a paper makes about its results.

    id : stable identifier (P1 ``p1-<section>-<topic>``, P2 ``<section>-<n>``); section : the paper's section;
    statement : the claim in short (the paper's words where possible); criterion : how it is judged here, either
    a template whose ``{tolerance}`` fields `criterion_text` fills from the paper's tolerance record, or a function
    of that record; judge : the function judging it (its arguments are the paper's: P1 (SystemData, tolerances) or
    (ClaimContext); P2 (context)); paper : the paper's value, one for all, per system role (a mapping), NaN when
    the claim is qualitative, or the paper's words; scope : whom the claim is about, in the paper's terms (P1: the
    system roles, None for every system; P2: "frictional", "frictionless", "both", "tables"); per_system : one row
    per system of the scope (else one row across systems); needs_rho_j : the judge needs the system's ρ_J.
    """

    id: str
    section: str
    statement: str
    criterion: str | Callable[[Any], str]
    judge: Callable = field(repr=False)
    paper: float | str | Mapping[Any, float] = math.nan
    scope: Any = None
    per_system: bool = True
    needs_rho_j: bool = True

    def paper_value(self, key: Any = None) -> float | str:
        """The paper's value for the system role `key` (NaN where a mapping has none), or its one value."""
        if isinstance(self.paper, Mapping):
            return float(self.paper.get(key, math.nan))
        return self.paper if isinstance(self.paper, str) else float(self.paper)

    def criterion_text(self, tolerances: Any) -> str:
        """The criterion with the tolerances filled in (a field that is None reads "per system")."""
        if callable(self.criterion):
            return self.criterion(tolerances)
        values = asdict(tolerances) if is_dataclass(tolerances) else dict(tolerances)
        return self.criterion.format(**{k: ("per system" if v is None else v) for k, v in values.items()})


def claim_register(claims: list[Claim]) -> Callable[..., Callable]:
    """A decorator factory ``claim(id, section, statement, criterion, **fields)`` that appends the decorated judge
    as a `Claim` to `claims` (in definition order) and returns the judge unchanged."""
    def claim(id: str, section: str, statement: str, criterion: str | Callable, **options) -> Callable:
        """The decorator registering one claim (the fields of `Claim` besides the judge)."""
        def register(judge: Callable) -> Callable:
            """Append `judge` as the claim's `Claim` and return it unchanged."""
            claims.append(Claim(id=id, section=section, statement=statement, criterion=criterion, judge=judge,
                                **options))
            return judge
        return register
    return claim


@dataclass(frozen=True)
class Explanation:
    """Why a claim does not hold: the text, and its basis — `MEASURED` with the command that measured it, or
    `HYPOTHESIS` (a cause proposed, not measured)."""

    text: str
    command: str = ""

    @property
    def basis(self) -> str:
        """``measured: <command>`` when a command measured it, else `HYPOTHESIS`."""
        return f"{MEASURED}: {self.command}" if self.command else HYPOTHESIS


#: the day the judges of issue 53's referee reading changed, after the campaign's verdicts had been read
JUDGE_CHANGE_DATE = "2026-12-05"


@dataclass(frozen=True)
class JudgeChange:
    """A change of a claim's judge made after its verdicts were read (the table's column
    ``judge_changed_after_reading``): the date, the rule now applied, and the verdict each row had under the old
    judge (``before``: {system: verdict[, marker]}, read from the committed campaign table of that day; "" every
    row) and the systems it concerns (`systems`, empty: every one)."""

    rule: str
    before: Mapping[str, str] = field(default_factory=dict)
    systems: tuple[str, ...] = ()
    date: str = JUDGE_CHANGE_DATE

    def text(self, system: str, reading: str = "") -> str:
        """The column's cell of the row of `system` under `reading`: the date and rule, and on the table's own
        reading the verdict before ("" key: the same for every system); "" for a system the change leaves alone
        (`systems`: the systems it concerns, empty for all)."""
        if self.systems and system not in self.systems:
            return ""
        before = self.before.get(system, self.before.get("", "")) if not reading else ""
        return f"{self.date}: {self.rule}" + (f" (before: {before})" if before else "")


@dataclass(frozen=True)
class JudgedClaim:
    """One row of a validation table, the same record for both papers. kind : ``"claim"``, or ``"value"`` for a
    number set beside the paper's without a criterion (P1's ρ_J, ρ_max …); system : the system(s) judged; paper :
    the paper's value (number or words); measured : our key number (NaN if none); evidence : what was measured;
    verdict : `HOLDS`, `FAILS`, `NOT_EVALUATED` (or "" for a value row with a value); marker : `MARGINAL`,
    `VACUOUS` or ""; states : the states (ρ) that carry the verdict; robustness : the share of bootstrap
    resamples of the realizations under which the claim holds (`judge_claim`; NaN where not computed);
    reading : "" for the table's conventions, else the other reading this row is judged under (set beside the
    primary row of the same claim); explanation, explanation_basis : why it does not hold and on what basis
    (`Explanation`); judge_changed_after_reading : where the claim's judge changed after its verdicts were read,
    the date, the rule and the verdict before (`JudgeChange`). robustness is text ("one run: …") where the
    verdict rests on a single run that no resample varies (`one_run_text`)."""

    id: str
    section: str
    statement: str
    system: str
    paper: float | str
    criterion: str
    measured: float
    evidence: str
    verdict: str
    kind: str = "claim"
    marker: str = ""
    states: str = ""
    robustness: float | str = math.nan
    reading: str = ""
    explanation: str = ""
    explanation_basis: str = ""
    judge_changed_after_reading: str = ""

    @property
    def difference(self) -> float:
        """measured − paper where both are finite numbers, else NaN."""
        if isinstance(self.paper, str):
            return math.nan
        measured, paper = float(self.measured), float(self.paper)
        return measured - paper if np.isfinite(measured) and np.isfinite(paper) else math.nan


def holds_share(judges: Sequence[Callable[[], Judgement]]) -> float:
    """The share of `judges` (one claim judged on each bootstrap resample of the realizations) under which the
    claim holds, among those that could judge it; NaN when none could (or there are none)."""
    outcomes = []
    for judge in judges:
        try:
            outcomes.append(bool(judge().holds))
        except NotEvaluated:
            continue
    return float(np.mean(outcomes)) if outcomes else math.nan


def one_run_text(runs: Sequence[str], share: float = math.nan) -> str:
    """The robustness cell of a verdict that rests on a single run of each of `runs`: it says so, with the share of
    resamples of the other systems' realizations under which it holds where there is one."""
    text = f"one run: {', '.join(runs)}"
    return text + (f" ({share:.2g} over the resamples of the others)" if np.isfinite(share) else "")


def judge_claim(claim: Claim, system: str, paper: float | str, criterion: str, judge: Callable[[], Judgement],
                explain: Callable[[str], Explanation | None] | None = None,
                resampled: Sequence[Callable[[], Judgement]] = (), reading: str = "",
                changed: JudgeChange | None = None, one_run: Sequence[str] = ()) -> JudgedClaim:
    """Run `judge` and record its verdict: `HOLDS` / `FAILS` from the `Judgement` with its marker, `NOT_EVALUATED`
    (the reason as evidence) when it raises `NotEvaluated`. `explain(verdict)` gives the explanation of a verdict
    (or None); `resampled` are the same judge on bootstrap resamples of the realizations (`holds_share`: the row's
    robustness); `reading` names the other reading the row is judged under ("" for the table's own); `changed`
    marks a judge changed after its verdicts were read (`JudgeChange`). A verdict resting on a single run (the
    judgement's `one_run`, or `one_run`: the row's system has one realization) says so in its robustness on the
    table's own reading (`one_run_text`) instead of a share no resample can vary."""
    marker = states = ""
    runs: tuple[str, ...] = tuple(one_run)
    try:
        judgement = judge()
        measured, evidence, verdict = judgement.measured, judgement.evidence, HOLDS if judgement.holds else FAILS
        marker, states = judgement.marker, judgement.states
        runs = tuple(dict.fromkeys((*judgement.one_run, *runs)))
    except NotEvaluated as reason:
        measured, evidence, verdict = math.nan, str(reason), NOT_EVALUATED
    explanation = explain(verdict) if explain else None
    robustness: float | str = holds_share(resampled) if verdict != NOT_EVALUATED else math.nan
    if runs and verdict != NOT_EVALUATED and not reading:
        robustness = one_run_text(runs, robustness)
    return JudgedClaim(id=claim.id, section=claim.section, statement=claim.statement, system=system, paper=paper,
                       criterion=criterion, measured=float(measured), evidence=evidence, verdict=verdict,
                       marker=marker, states=states, robustness=robustness,
                       reading=reading, explanation=explanation.text if explanation else "",
                       explanation_basis=explanation.basis if explanation else "",
                       judge_changed_after_reading=changed.text(system, reading) if changed else "")


def rows_beside(primary: Sequence[JudgedClaim], other: Sequence[JudgedClaim]) -> list[JudgedClaim]:
    """The rows of `other` (the same claims judged under another reading, row for row) that differ from `primary`
    in verdict, marker or key number (4 significant digits, as the table prints it): the rows set beside."""
    def key(row: JudgedClaim) -> tuple:
        """What a reader compares between the two rows."""
        return row.verdict, row.marker, f"{row.measured:.4g}"

    return [row for row, first in zip(other, primary, strict=True) if key(row) != key(first)]


def verdict_counts(table: pd.DataFrame) -> dict[str, int]:
    """How many claim rows (all rows of a table without a ``kind`` column) of the table's own reading hold, do not
    hold, are not evaluated; and, counted apart, how many of them carry each marker (`MARGINAL`, `VACUOUS`) and
    how many verdicts are fair (no marker)."""
    claims = table[table["kind"] == "claim"] if "kind" in table else table
    if "reading" in claims:
        claims = claims[claims["reading"].fillna("") == ""]
    counts = {verdict: int((claims["verdict"] == verdict).sum()) for verdict in (HOLDS, FAILS, NOT_EVALUATED)}
    markers = claims["marker"].fillna("") if "marker" in claims else pd.Series("", index=claims.index)
    judged = claims["verdict"].isin((HOLDS, FAILS))
    counts.update({marker: int(((markers == marker) & judged).sum()) for marker in (MARGINAL, VACUOUS)})
    counts["fair"] = int(((markers == "") & judged).sum())
    return counts


def verdict_summary(table: pd.DataFrame) -> str:
    """The verdict counts as one line: "N rows: a hold, b do not hold, c not evaluated; of the d judged, e fair,
    f marginal, g vacuous"."""
    counts = verdict_counts(table)
    judged = counts[HOLDS] + counts[FAILS]
    rows = judged + counts[NOT_EVALUATED]
    return (f"{rows} rows: {counts[HOLDS]} hold, {counts[FAILS]} do not hold, {counts[NOT_EVALUATED]} not "
            f"evaluated; of the {judged} judged, {counts['fair']} fair, {counts[MARGINAL]} {MARGINAL}, "
            f"{counts[VACUOUS]} {VACUOUS}.")
