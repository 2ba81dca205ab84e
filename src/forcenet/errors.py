"""The base of forcenet's expected errors: bad input, an invalid file, a simulation that became unphysical.

Their message is the whole story (it names the file, the config key or the setting to change), so a workflow job
reports them as one line without a traceback (`forcenet.pipeline.job_logger`); any other exception is a bug and
keeps its traceback.
"""


class ForcenetError(Exception):
    """An error whose one-line message tells the user what is wrong and where."""
