"""The parts of report/ both papers share: the mean and spread over realizations, the claims framework, and the
column of paper-size values read from the validation campaign's committed tables (docs/validation/)."""
from __future__ import annotations

import math
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from forcenet.report import claims, claims_table, p1_validation, p2_validation, realizations
from forcenet.report.claims_table import PAPER_SIZE, PAPER_SIZE_HEADER


# --- reductions over realizations -------------------------------------------------------------------------------
def per_realization(values) -> xr.DataArray:
    """(realization, rho) values on ρ = 0.70, 0.71, …"""
    values = np.asarray(values, dtype=float)
    return xr.DataArray(values, dims=("realization", "rho"),
                        coords={"rho": 0.70 + 0.01 * np.arange(values.shape[1])})


def test_mean_and_spread_are_the_mean_and_sample_std_of_the_finite_realizations():
    da = per_realization([[1.0, 2.0, np.nan], [2.0, 4.0, 5.0], [3.0, 9.0, np.nan]])
    mean, spread = realizations.mean_and_spread(da)
    np.testing.assert_allclose(mean, [2.0, 5.0, 5.0])
    # ρ0: std of 1, 2, 3 with ddof = 1 is 1; ρ1: of 2, 4, 9 is sqrt(13); ρ2: one finite value, spread 0
    np.testing.assert_allclose(spread, [1.0, math.sqrt(13.0), 0.0])


def test_a_single_realization_has_no_spread_and_a_selected_one_is_unchanged():
    one = per_realization([[1.0, 3.0]])
    np.testing.assert_array_equal(realizations.realization_spread(one), [0.0, 0.0])
    np.testing.assert_array_equal(realizations.realization_mean(one), [1.0, 3.0])
    selected = one.isel(realization=0)
    assert realizations.realization_mean(selected) is selected
    np.testing.assert_array_equal(realizations.realization_spread(selected), [0.0, 0.0])


def test_all_nan_point_has_a_nan_mean():
    mean, spread = realizations.mean_and_spread(per_realization([[np.nan, 1.0], [np.nan, 3.0]]))
    assert np.isnan(mean[0]) and spread[0] == 0 and mean[1] == 2.0


# --- the claims framework ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Tolerances:
    factor: float = 1.5
    window: float | None = None


def record(criterion="value within a factor {factor} (window {window})", paper=2.0) -> claims.Claim:
    return claims.Claim(id="x-1", section="4", statement="x is about 2", criterion=criterion, judge=lambda: None,
                        paper=paper)


@pytest.mark.parametrize("measured, expected", [(2.5, claims.HOLDS), (4.0, claims.FAILS)])
def test_a_judgement_gives_the_verdict_and_the_difference(measured, expected):
    claim = record()
    judged = claims.judge_claim(claim, "sys", claim.paper_value(), claim.criterion_text(Tolerances()),
                                lambda: claims.Judgement(measured, f"x = {measured}", measured <= 2.0 * 1.5))
    assert judged.verdict == expected and judged.evidence == f"x = {measured}"
    assert judged.criterion == "value within a factor 1.5 (window per system)"
    assert judged.difference == pytest.approx(measured - 2.0)


def test_a_claim_the_data_cannot_decide_is_not_evaluated_with_the_reason():
    def judge():
        raise claims.NotEvaluated("no rho below rho_J")

    judged = claims.judge_claim(record(), "sys", 2.0, "c", judge,
                                explain=lambda verdict: claims.Explanation(f"why: {verdict}"))
    assert (judged.verdict, judged.evidence, judged.explanation) == (claims.NOT_EVALUATED, "no rho below rho_J",
                                                                     "why: not evaluated")
    assert judged.explanation_basis == claims.HYPOTHESIS and judged.marker == ""
    assert math.isnan(judged.measured) and math.isnan(judged.difference) and math.isnan(judged.robustness)


def test_an_explanation_says_measured_with_its_command_or_hypothesis():
    assert claims.Explanation("few contacts", "python scripts/p2_sampling.py").basis == (
        "measured: python scripts/p2_sampling.py")
    assert claims.Explanation("few realizations").basis == claims.HYPOTHESIS


# --- markers (issue 25): marginal within 10 % of the threshold or one grid step, vacuous passes ----------------
@pytest.mark.parametrize("judgement, marker", [
    (claims.Judgement(1.05, "e", True, margin=claims.relative_margin(1.05, 1.0)), claims.MARGINAL),
    (claims.Judgement(0.95, "e", False, margin=claims.relative_margin(0.95, 1.0)), claims.MARGINAL),
    (claims.Judgement(1.5, "e", True, margin=claims.relative_margin(1.5, 1.0)), ""),
    (claims.Judgement(1.5, "e", True, margin=0.5, grid_step=True), claims.MARGINAL),
    (claims.Judgement(0.0, "e", True, vacuous=True), claims.VACUOUS),
    (claims.Judgement(0.0, "e", False, vacuous=True), ""),  # a vacuous quantity that fails is a plain failure
    (claims.Judgement(math.nan, "e", True), ""),
])
def test_a_verdict_near_its_threshold_is_marginal_and_one_on_zeros_vacuous(judgement, marker):
    assert judgement.marker == marker
    judged = claims.judge_claim(record(), "sys", 2.0, "c", lambda: judgement)
    assert judged.marker == marker


def test_margins_are_relative_to_the_threshold_or_the_larger_number():
    assert claims.relative_margin(1.1, 1.0) == pytest.approx(0.1)
    assert claims.relative_margin(0.0, 0.0) == 0.0 and claims.relative_margin(1.0, 0.0) == math.inf
    assert claims.contrast_margin(0.9, 1.0) == pytest.approx(0.1) and claims.contrast_margin(0, 0) == 0.0
    assert claims.ratio_margin(10.0, 10.0) == 0.0 and claims.ratio_margin(100.0, 10.0) == pytest.approx(1.0)
    assert claims.smallest_margin(math.nan, 0.3, 0.2) == 0.2 and math.isnan(claims.smallest_margin(math.nan))


def test_robustness_is_the_share_of_resamples_under_which_the_claim_holds():
    def judged(holds):
        def judge():
            if holds is None:
                raise claims.NotEvaluated("too few")
            return claims.Judgement(1.0, "e", holds)
        return judge

    row = claims.judge_claim(record(), "sys", 2.0, "c", judged(True),
                             resampled=[judged(True), judged(False), judged(True), judged(None), judged(False)])
    assert row.robustness == pytest.approx(0.5)  # 2 of the 4 resamples that could judge it
    assert math.isnan(claims.holds_share([judged(None)])) and math.isnan(claims.holds_share([]))


def test_verdict_counts_count_markers_apart_and_only_the_tables_own_reading():
    common = dict(section="4", statement="s", criterion="c", evidence="e", paper=math.nan, measured=1.0)
    rows = [claims.JudgedClaim(id="a", system="x", verdict=claims.HOLDS, **common),
            claims.JudgedClaim(id="b", system="x", verdict=claims.HOLDS, marker=claims.VACUOUS, **common),
            claims.JudgedClaim(id="c", system="x", verdict=claims.FAILS, marker=claims.MARGINAL, **common),
            claims.JudgedClaim(id="d", system="x", verdict=claims.NOT_EVALUATED, **common),
            claims.JudgedClaim(id="a", system="x", verdict=claims.FAILS, reading="other", **common)]
    table = pd.DataFrame([{**vars(r)} for r in rows])
    counts = claims.verdict_counts(table)
    assert counts == {claims.HOLDS: 2, claims.FAILS: 1, claims.NOT_EVALUATED: 1, claims.MARGINAL: 1,
                      claims.VACUOUS: 1, "fair": 1}
    assert claims.verdict_summary(table) == ("4 rows: 2 hold, 1 do not hold, 1 not evaluated; of the 3 judged, "
                                             "1 fair, 1 marginal, 1 vacuous.")


def test_the_paper_value_is_per_role_or_words():
    per_role = record(paper={(2, "hertz"): 1.5})
    assert per_role.paper_value((2, "hertz")) == 1.5 and math.isnan(per_role.paper_value((3, "hertz")))
    assert record(paper="larger / same").paper_value() == "larger / same"
    assert record(criterion=lambda t: f"f = {t.factor}").criterion_text(Tolerances()) == "f = 1.5"


def test_claim_register_keeps_the_definition_order():
    registered: list[claims.Claim] = []
    claim = claims.claim_register(registered)

    @claim("b-2", "5", "second", "c")
    def second():
        return "judged"

    claim("a-1", "4", "first", "c", paper=1.0)(lambda: None)
    assert [c.id for c in registered] == ["b-2", "a-1"] and second() == "judged"


# --- the paper-size column (issue #14) ----------------------------------------------------------------------------
def judged_rows() -> list[claims.JudgedClaim]:
    common = dict(section="4", statement="s", criterion="c", evidence="e")
    return [claims.JudgedClaim(id="rho_J", system="2d_hertz", paper=0.842, measured=0.78, verdict="", kind="value",
                               **common),
            claims.JudgedClaim(id="p1-4-x", system="2d_hertz", paper=math.nan, measured=0.5, verdict=claims.HOLDS,
                               **common),
            claims.JudgedClaim(id="p1-4-x", system="3d_hertz", paper=math.nan, measured=0.1, verdict=claims.FAILS,
                               **common)]


def campaign_csv(path, rows: list[dict]) -> str:
    """A campaign table as `forcenet.report.validation` writes it: provenance lines, then the rows."""
    text = "# study: p1\n# git_commit: abc\n" + pd.DataFrame(rows).to_csv(index=False)
    path.write_text(text)
    return str(path)


def test_paper_size_values_stand_beside_the_papers_matched_by_id_and_system(tmp_path):
    table = claims_table.claims_frame(judged_rows(), p1_validation.P1_LAYOUT)
    docs = campaign_csv(tmp_path / "p1.csv", [
        {"table": "P1 validation table", "kind": "value", "id": "rho_J", "system": "2d_hertz", "measured": 0.80512,
         "verdict": ""},
        {"table": "P1 validation table", "kind": "claim", "id": "p1-4-x", "system": "2d_hertz", "measured": 0.25,
         "verdict": "does not hold"}])
    shown = claims_table.with_paper_size(table, p1_validation.P1_LAYOUT, docs)
    columns = list(shown.columns)
    assert columns.index(PAPER_SIZE) == columns.index("paper") + 1
    assert list(shown[PAPER_SIZE]) == ["0.8051", "0.25 (does not hold)", f"not in {docs}"]
    assert list(shown.drop(columns=PAPER_SIZE).columns) == list(table.columns)  # every other column kept


def test_a_missing_campaign_table_gives_the_placeholder(tmp_path):
    table = claims_table.claims_frame(judged_rows(), p1_validation.P1_LAYOUT)
    missing = tmp_path / "docs" / "p1.csv"
    shown = claims_table.with_paper_size(table, p1_validation.P1_LAYOUT, missing)
    assert set(shown[PAPER_SIZE]) == {f"not yet run ({missing} missing)"}


def test_a_campaign_table_without_the_key_columns_is_refused(tmp_path):
    table = claims_table.claims_frame(judged_rows(), p1_validation.P1_LAYOUT)
    docs = campaign_csv(tmp_path / "p1.csv", [{"claim": "x", "verdict": "holds"}])
    with pytest.raises(ValueError, match="not a validation table"):
        claims_table.with_paper_size(table, p1_validation.P1_LAYOUT, docs)


def test_a_table_without_the_attribute_its_reader_needs_is_refused_naming_it(tmp_path):
    table = claims_table.claims_frame(judged_rows(), p1_validation.P1_LAYOUT)  # by hand: no force_unit
    with pytest.raises(claims_table.TableAttributeError, match="^the table has no attribute 'force_unit' \\(set by "
                                                               "p1_validation, which every reader of it needs\\)"):
        p1_validation.write_p1_validation(table, tmp_path / "t.csv", tmp_path / "t.md")
    assert not (tmp_path / "t.md").exists()
    table.attrs["force_unit"] = "reduced"  # as p1_validation sets it
    p1_validation.write_p1_validation(table, tmp_path / "t.csv", tmp_path / "t.md")
    assert "reduced" in (tmp_path / "t.md").read_text()


def test_p1_table_writes_the_paper_size_column_in_csv_and_markdown(tmp_path):
    table = claims_table.claims_frame(judged_rows(), p1_validation.P1_LAYOUT)
    table.attrs.update(force_unit="reduced", left_out="")  # as p1_validation sets them
    docs = campaign_csv(tmp_path / "p1.csv", [{"id": "rho_J", "system": "2d_hertz", "measured": 0.805,
                                               "verdict": ""}])
    p1_validation.write_p1_validation(table, tmp_path / "t.csv", tmp_path / "t.md", paper_size=docs)
    back = pd.read_csv(tmp_path / "t.csv")
    assert list(back.columns) == [*p1_validation.COLUMNS[:7], PAPER_SIZE, *p1_validation.COLUMNS[7:]]
    assert back.loc[0, PAPER_SIZE] == "0.805"
    md = (tmp_path / "t.md").read_text()
    assert f"| item | system | measured | paper | {PAPER_SIZE_HEADER} | difference |" in md
    assert "| 0.78 | 0.842 | 0.805 | -0.062 |" in md and docs in md
    p1_validation.write_p1_validation(table, tmp_path / "plain.csv", tmp_path / "plain.md")  # no campaign table
    assert PAPER_SIZE not in pd.read_csv(tmp_path / "plain.csv") and PAPER_SIZE_HEADER not in (
        tmp_path / "plain.md").read_text()


def test_p2_table_shows_the_campaign_evidence_and_verdict_beside_p2s_words(tmp_path):
    row = claims.JudgedClaim(id="IV.C-1", section="§IV C", statement="jams later", system="mu05 vs mu0",
                             paper="rho_J(mu=0) > rho_J(mu=0.5)", criterion="c", measured=math.nan,
                             evidence="rho_J 0.80, 0.83", verdict=claims.HOLDS)
    table = claims_table.claims_frame([row], p2_validation.P2_LAYOUT)
    table.attrs.update(systems={}, tolerances=p2_validation.ClaimTolerances())  # as p2_validation sets them
    docs = campaign_csv(tmp_path / "p2.csv", [
        {"table": "P2 validation table", "claim_id": "IV.C-1", "system": "mu05 vs mu0", "measured": "rho_J 0.802, 0.833",
         "verdict": "holds"},
        {"table": "Table I", "claim_id": "", "system": "", "measured": "", "verdict": ""}])
    p2_validation.write_p2_validation(table, tmp_path / "t.csv", tmp_path / "t.md", paper_size=docs)
    back = pd.read_csv(tmp_path / "t.csv")
    assert list(back.columns).index(PAPER_SIZE) == list(back.columns).index("reference") + 1
    assert back.loc[0, PAPER_SIZE] == "rho_J 0.802, 0.833 (holds)"
    md = (tmp_path / "t.md").read_text()
    assert (f"| id | section | system | claim | P2 | {PAPER_SIZE_HEADER} | criterion | measured | evidence | verdict | "
            "marker |") in md
    assert "| rho_J(mu=0) > rho_J(mu=0.5) | rho_J 0.802, 0.833 (holds) | c |" in md


def test_bootstrap_draws_keep_a_single_realization_in_every_draw():
    import xarray as xr

    from forcenet.report.realizations import bootstrap_draws

    def runs(n):
        return xr.Dataset({"x": ("realization", np.arange(float(n)))})

    draws = bootstrap_draws({"five": runs(5), "one": runs(1)}, 20, seed=3)
    assert len(draws) == 20 and all(list(d["one"]) == [0] for d in draws)
    assert len({tuple(d["five"]) for d in draws}) > 1 and all(len(d["five"]) == 5 for d in draws)
    assert bootstrap_draws({"one": runs(1), "also one": runs(1)}, 20) == []
    # a system's draws are its own: judging another system beside it (a counterpart, say) leaves them alone
    beside = bootstrap_draws({"five": runs(5), "one": runs(1), "another five": runs(5), "a": runs(3)}, 20, seed=3)
    assert [list(d["five"]) for d in beside] == [list(d["five"]) for d in draws]
    assert [list(d["another five"]) for d in beside] != [list(d["five"]) for d in beside]


# --- two tables of one paper, verdict by verdict ------------------------------------------------------------------
def campaign_rows(changed: dict | None = None) -> list[dict]:
    """A P1 campaign table's rows: a value row (no verdict), a claim judged on two systems, one judged under a
    reading beside; `changed` maps (id, system, reading) to the fields that differ."""
    rows = [dict(table="P1 validation table", kind="value", id="rho_J", system="2d_hertz", reading="",
                 measured="0.817", verdict="", marker="", robustness=""),
            dict(table="P1 validation table", kind="claim", id="p1-4-x", system="2d_hertz", reading="",
                 measured="0.5", verdict=claims.HOLDS, marker="", robustness="1.0"),
            dict(table="P1 validation table", kind="claim", id="p1-4-x", system="3d_hertz", reading="",
                 measured="0.1", verdict=claims.FAILS, marker=claims.MARGINAL, robustness="0.2"),
            dict(table="P1 validation table", kind="claim", id="p1-4-x", system="3d_hertz", reading="other",
                 measured="0.3", verdict=claims.HOLDS, marker="", robustness="0.9")]
    for row in rows:
        row.update((changed or {}).get((row["id"], row["system"], row["reading"]), {}))
    return [row for row in rows if row.get("drop") is None]


def test_verdict_changes_lists_each_changed_verdict_marker_or_robustness_and_nothing_else():
    before = pd.DataFrame(campaign_rows())
    # only the measured values move: no change (a new realization moves every number)
    moved = pd.DataFrame(campaign_rows({("p1-4-x", "2d_hertz", ""): dict(measured="0.51"),
                                          ("rho_J", "2d_hertz", ""): dict(measured="0.819")}))
    assert claims_table.verdict_changes(before, moved).empty
    # unless the measured values are compared too (the same runs made again must give the same text)
    measured = claims_table.verdict_changes(before, moved, compared=("measured", *claims_table.COMPARED_COLUMNS))
    assert list(zip(measured["id"], measured["change"])) == [("rho_J", "measured"), ("p1-4-x", "measured")]
    with pytest.raises(ValueError, match="cannot compare"):
        claims_table.verdict_changes(before, moved, compared=("evidence",))
    after = pd.DataFrame(campaign_rows({("p1-4-x", "2d_hertz", ""): dict(verdict=claims.FAILS, robustness="0.4",
                                                                            measured="0.45"),
                                          ("p1-4-x", "3d_hertz", ""): dict(marker=""),
                                          ("p1-4-x", "3d_hertz", "other"): dict(robustness="0.8")}))
    changes = claims_table.verdict_changes(before, after)
    assert list(changes["change"]) == ["verdict, robustness", "marker", "robustness"]
    assert list(changes["system"]) == ["2d_hertz", "3d_hertz", "3d_hertz"]
    assert list(changes["reading"]) == ["", "", "other"]  # the reading beside is its own row
    first = changes.iloc[0]
    assert (first["verdict before"], first["verdict after"]) == (claims.HOLDS, claims.FAILS)
    assert (first["measured before"], first["measured after"]) == ("0.5", "0.45")
    assert (first["robustness before"], first["robustness after"]) == ("1.0", "0.4")


def test_verdict_changes_names_the_rows_only_one_table_has():
    before = pd.DataFrame(campaign_rows({("p1-4-x", "3d_hertz", "other"): dict(drop=True)}))
    after = pd.DataFrame(campaign_rows({("p1-4-x", "2d_hertz", ""): dict(drop=True)}))
    changes = claims_table.verdict_changes(before, after)
    assert list(zip(changes["system"], changes["reading"], changes["change"])) == [
        ("3d_hertz", "other", "only after"), ("2d_hertz", "", "only before")]
    only_after = changes.iloc[0]
    assert (only_after["verdict before"], only_after["verdict after"]) == ("", claims.HOLDS)
    assert claims_table.verdict_changes(before, before).empty


def test_verdict_changes_refuses_a_table_of_the_other_paper_or_with_a_repeated_row():
    p1 = pd.DataFrame(campaign_rows())
    p2 = p1.rename(columns={"id": "claim_id"})
    with pytest.raises(ValueError, match="no column 'id'"):
        claims_table.verdict_changes(p1, p2)
    doubled = pd.concat([p1, p1.iloc[[1]]])
    with pytest.raises(ValueError, match="rows with the same"):
        claims_table.verdict_changes(p1, doubled)
    # P2's tables: the claim id is `claim_id`, and Tables I–III rows (no claim id) are not compared
    p2_rows = p2.assign(table="P2 validation table")
    p2_rows.loc[len(p2_rows)] = dict(table="Table I", kind="", claim_id="", system="", reading="", measured="",
                                     verdict="", marker="", robustness="")
    assert claims_table.verdict_changes(p2_rows, p2_rows.iloc[:-1], id_column="claim_id").empty


def test_a_campaign_table_is_read_as_text_without_its_provenance(tmp_path):
    path = campaign_csv(tmp_path / "p1.csv", campaign_rows())
    table = claims_table.read_validation_csv(path)
    assert list(table["id"]) == ["rho_J", "p1-4-x", "p1-4-x", "p1-4-x"]
    assert table.loc[0, "verdict"] == "" and table.loc[1, "robustness"] == "1.0"  # text, empty cells ""
    # a "#" inside a cell is text, not a comment: only the leading provenance lines are skipped
    with_hash = campaign_csv(tmp_path / "hash.csv", campaign_rows({("p1-4-x", "2d_hertz", ""): dict(
        marker="see issue #24", measured="0.5")}))
    kept = claims_table.read_validation_csv(with_hash)
    assert kept.loc[1, "marker"] == "see issue #24" and kept.loc[1, "robustness"] == "1.0"
    typed = claims_table.read_validation_csv(with_hash, as_text=False)
    assert typed.loc[1, "measured"] == 0.5 and math.isnan(typed.loc[0, "robustness"])


def test_compare_verdicts_script_prints_both_tables_counts_and_the_changed_rows(tmp_path):
    script = Path(__file__).resolve().parents[1] / "scripts/compare_verdicts.py"
    before = campaign_csv(tmp_path / "before.csv", campaign_rows())
    after = campaign_csv(tmp_path / "after.csv",
                         campaign_rows({("p1-4-x", "2d_hertz", ""): dict(verdict=claims.FAILS)}))
    shown = subprocess.run([sys.executable, str(script), before, after, "--csv", str(tmp_path / "changes.csv")],
                           capture_output=True, text=True)
    assert shown.returncode == 0, shown.stderr
    assert "- git_commit: abc" in shown.stdout  # each table's provenance
    # the claim rows of the table's own reading (the reading beside is not counted)
    assert "2 rows: 1 hold, 1 do not hold, 0 not evaluated; of the 2 judged, 1 fair, 1 marginal" in shown.stdout
    assert "2 rows: 0 hold, 2 do not hold, 0 not evaluated" in shown.stdout  # after
    assert "## 1 rows changed (1 verdict)" in shown.stdout
    assert "| p1-4-x | P1 validation table | 2d_hertz |  | 0.5 | 0.5 | holds | does not hold |" in shown.stdout
    assert list(pd.read_csv(tmp_path / "changes.csv")["change"]) == ["verdict"]
    # the committed campaign table against itself at HEAD (REV:PATH read through git): nothing changed
    same = subprocess.run([sys.executable, str(script), "--measured", "HEAD:docs/validation/p1.csv",
                           "HEAD:docs/validation/p1.csv"], capture_output=True, text=True)
    assert same.returncode == 0 and "No measured, verdict, marker or robustness changed" in same.stdout, same.stderr
    missing = subprocess.run([sys.executable, str(script), str(tmp_path / "none.csv"), after],
                             capture_output=True, text=True)
    assert missing.returncode == 2 and "none.csv" in missing.stderr


def test_the_campaign_report_stacks_each_table_unchanged_under_its_provenance(tmp_path):
    from forcenet.report import validation

    frame = pd.DataFrame(campaign_rows({("p1-4-x", "2d_hertz", ""): dict(marker="see issue #24")})).drop(
        columns="table")
    frame.to_csv(tmp_path / "p1_validation.csv", index=False)
    (tmp_path / "p1_validation.md").write_text("| a |\n|---|\n| 1 |\n")
    costs = [{"system": "2d_hertz", "realization": 0, "cpu_seconds": 1800.0, "particles": 2025, "snapshots": 21},
             {"system": "2d_hertz", "realization": 1, "cpu_seconds": 1800.0, "particles": 2025, "snapshots": 21}]
    info = validation.provenance(study="p1", config={"systems": {}}, systems=["2d_hertz"], costs=costs,
                                 commit="abc", date="2026-11-27 17:00 UTC")
    validation.write_validation_report(info=info, title="P1", md_path=tmp_path / "p1.md", csv_path=tmp_path / "p1.csv",
                                       sections=[("P1 validation table", str(tmp_path / "p1_validation.md"),
                                                  str(tmp_path / "p1_validation.csv"))])
    text = (tmp_path / "p1.csv").read_text()
    assert text.startswith("# study: p1\n# git_commit: abc\n")
    assert "# system 2d_hertz: N=2025 realizations=2 cpu_hours=1.0\n" in text
    back = claims_table.read_validation_csv(tmp_path / "p1.csv")
    assert list(back.columns) == ["table", *frame.columns]
    assert set(back["table"]) == {"P1 validation table"}
    pd.testing.assert_frame_equal(back.drop(columns="table"), frame.astype(str).replace("nan", ""))
    assert back.loc[1, "marker"] == "see issue #24"  # a "#" in a cell is kept
    md = (tmp_path / "p1.md").read_text()
    assert "| 1 |" in md and "| 2d_hertz | 2025 | 2 | 1.00 |" in md


# --- a judge changed after its verdicts were read (issue 53) -------------------------------------------------------
def test_a_judge_change_names_its_date_rule_and_the_verdict_before():
    change = claims.JudgeChange("the rule now", {"a": "does not hold", "": "holds"}, systems=("a", "b"))
    assert change.text("a") == "2026-12-05: the rule now (before: does not hold)"
    assert change.text("b") == "2026-12-05: the rule now (before: holds)"  # "" covers every other row
    assert change.text("a", reading="another reading") == "2026-12-05: the rule now"  # its verdict before is unknown
    assert change.text("c") == ""  # a system the change leaves alone
    claim = claims.Claim(id="x-1", section="1", statement="s", criterion="c", judge=lambda: None)
    row = claims.judge_claim(claim, "a", math.nan, "c", lambda: claims.Judgement(1.0, "e", True), changed=change)
    assert row.judge_changed_after_reading == change.text("a")
    assert claims.judge_claim(claim, "a", math.nan, "c", lambda: claims.Judgement(1.0, "e", True)
                              ).judge_changed_after_reading == ""


def test_a_verdict_on_one_run_says_so_instead_of_a_share():
    claim = claims.Claim(id="x-1", section="1", statement="s", criterion="c", judge=lambda: None)
    judged = claims.Judgement(1.0, "e", True, one_run=("b_mu0",))
    row = claims.judge_claim(claim, "all", math.nan, "c", lambda: judged, resampled=[lambda: judged] * 4)
    assert row.robustness == "one run: b_mu0 (1 over the resamples of the others)"
    # resting on runs with realizations of their own: the share
    plain = claims.Judgement(1.0, "e", True)
    assert claims.judge_claim(claim, "all", math.nan, "c", lambda: plain, resampled=[lambda: plain] * 4).robustness == 1.0
    # a row whose system has one realization, nothing resampled: one run, no share; not evaluated: nothing
    assert claims.judge_claim(claim, "a", math.nan, "c", lambda: plain, one_run=("a",)).robustness == "one run: a"

    def missing():
        raise claims.NotEvaluated("no data")
    assert math.isnan(claims.judge_claim(claim, "a", math.nan, "c", missing, one_run=("a",)).robustness)


def test_a_margin_against_the_papers_own_value_and_an_infinite_ratio():
    # P2's quotient 2.91 lies log(2.91) from 1: ours at 1.105 covers under a tenth of it, 1.5 more than a third
    assert claims.reference_margin(1.105, 1.0, 2.91) == pytest.approx(math.log(1.105) / math.log(2.91))
    assert claims.reference_margin(1.5, 1.0, 2.91) > 0.35
    assert math.isnan(claims.reference_margin(1.2, 1.0, 1.0)) and math.isnan(claims.reference_margin(-1, 1.0, 2.0))
    # a ratio of 0 or inf lies infinitely far from its factor on a log scale: a margin, not none
    assert claims.ratio_margin(math.inf, 2.0) == math.inf and claims.ratio_margin(0.0, 2.0) == math.inf
    assert math.isnan(claims.ratio_margin(math.nan, 2.0)) and math.isnan(claims.ratio_margin(2.0, 1.0))
