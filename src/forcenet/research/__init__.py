"""Research tools beside the pipeline: measurements the documents cite, run by the scripts in `scripts/`, not by
the workflow. `survey`: compressions of one system under config overrides, each snapshot's state tabulated
(scripts/compression_survey.py, scripts/run_states.py); `damping_series`: the Hertz damping series' readings of
finished runs (scripts/damping_series.py, docs/validation/damping.md)."""
