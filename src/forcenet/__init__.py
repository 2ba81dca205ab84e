"""forcenet: force networks in compressed granular matter (DEM, persistent homology, netCDF)."""
from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("forcenet")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0+unknown"
