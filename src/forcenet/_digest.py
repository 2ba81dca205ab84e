"""A digest of source files (standard library only): what numba's kernel cache folder is named after
(`forcenet._numba.kernel_cache_dir`) and what makes the workflow's claim tables rerun when their judges' code
changes (`workflow/rules/common.smk`, `JUDGES_DIGEST`)."""
from __future__ import annotations

import hashlib
from pathlib import Path

#: the package's own folder
PACKAGE = Path(__file__).resolve().parent


def sources_digest(package: Path, patterns) -> str:
    """sha256 (16 hex digits) of the files matching `patterns` (globs) under `package`, names and contents."""
    digest = hashlib.sha256()
    for path in sorted({path for pattern in patterns for path in package.glob(pattern)}):
        digest.update(path.relative_to(package).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]
