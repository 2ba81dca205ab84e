"""Paper reports: the reductions the papers' figures share, and the validation tables that set measured values
beside the papers' and judge their claims. One module per job:

- `realizations` — the one convention for the mean and spread over realizations (P1, P2, tables and figures).
- `claims` — the claims framework of both papers: a claim, its judgement, the validation table (CSV and Markdown)
  and the column of our paper-size values from ``docs/validation/``.
- `validation` — the committed tables of the validation campaign (``docs/validation/{p1,p2}.{md,csv}``).
- P1: `p1` (reference values and reductions: F_max rule, ρ_J, percolation, force PDF, S_p averaging),
  `p1_judging` (tolerances, the data a judge sees, shared judge helpers), `p1_claims` (§3–4, §6),
  `p1_claims_topology` (§5), `p1_validation` (the table).
- P2: `p2` (what P2 compares, reductions: ratios, ρ_J, quoted levels), `p2_distances` (diagram adapters, the
  ``distances.nc`` product, lagged distances), `p2_tables` (Tables I–III and their states a, b, c),
  `p2_judging` (tolerances, curves, context), `p2_claims` (§III D–§V), `p2_explanations` (why a claim does not
  hold), `p2_validation` (the table).

Modules are imported by their full name (``from forcenet.report import p2_validation``); this package imports
none of them itself.
"""
