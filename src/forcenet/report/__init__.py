"""Paper reports: validation tables that set measured values beside the papers' and judge their claims."""
from forcenet.report.p1 import (FMaxCut, cut_at_rho_max, f_max_cut, p1_validation, p1_validation_markdown,
                                write_p1_validation)

__all__ = ["FMaxCut", "cut_at_rho_max", "f_max_cut", "p1_validation", "p1_validation_markdown",
           "write_p1_validation"]
