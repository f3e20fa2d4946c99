"""The global-land-mask data without loading it whole.

The package holds a 21,600 x 43,200 boolean grid (about 1 km cells) that its own module
decompresses into 933 MB at import. Here the grid is streamed once out of the package's npz into
bit-packed bands of BAND_ROWS rows (a few MB in all, in the user cache directory or
COUNTERSIGN_LAND_MASK_CACHE) and each band is loaded when a point falls in it.
"""

from __future__ import annotations

import importlib.util
import os
import tempfile
import threading
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import platformdirs

from ..settings import InstallationEnvironment, read

ROWS, COLS = 21_600, 43_200
BAND_ROWS = 600  # 5 degrees of latitude
CACHE_NAME = "land-mask-v1.npz"
_LOCK = threading.Lock()
_BANDS: dict[int, np.ndarray] = {}
_AXES: dict[str, np.ndarray] = {}


def _package_file() -> Path:
    spec = importlib.util.find_spec("global_land_mask")
    if spec is None or spec.origin is None:
        raise RuntimeError("the global-land-mask package is not installed")
    return Path(spec.origin).parent / "globe_combined_mask_compressed.npz"


def cache_path() -> Path:
    given = read(InstallationEnvironment).land_mask_cache
    if given is not None:
        return given
    return Path(platformdirs.user_cache_dir("countersign")) / CACHE_NAME


def _build(target: Path) -> None:
    source = _package_file()
    bands: dict[str, np.ndarray] = {}
    with zipfile.ZipFile(source) as archive:
        with archive.open("lat.npy") as handle:
            bands["lat"] = np.lib.format.read_array(handle)
        with archive.open("lon.npy") as handle:
            bands["lon"] = np.lib.format.read_array(handle)
        with archive.open("mask.npy") as stream:
            version = np.lib.format.read_magic(stream)
            read_header = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                           else np.lib.format.read_array_header_2_0)
            shape, fortran, dtype = read_header(stream)
            if tuple(shape) != (ROWS, COLS) or fortran or dtype != np.bool_:
                raise RuntimeError(f"unexpected land mask layout {shape} {dtype}")
            for band in range(ROWS // BAND_ROWS):
                raw = stream.read(BAND_ROWS * COLS)
                rows = np.frombuffer(raw, dtype=np.uint8).reshape(BAND_ROWS, COLS)
                bands[f"b{band}"] = np.packbits(rows.astype(bool), axis=1)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=target.parent, suffix=".npz")
    os.close(fd)
    np.savez_compressed(tmp, **bands)  # type: ignore[arg-type]
    os.replace(tmp, target)


def _archive() -> Any:
    path = cache_path()
    if not path.exists():
        _build(path)
    return np.load(path)


def _band(index: int) -> np.ndarray:
    """The band's bits, still packed eight cells to a byte (unpacking a band is 26 MB)."""
    with _LOCK:
        if index not in _BANDS:
            with _archive() as data:
                _BANDS[index] = data[f"b{index}"]
        return _BANDS[index]


def _axes() -> tuple[np.ndarray, np.ndarray]:
    with _LOCK:
        if not _AXES:
            with _archive() as data:
                _AXES["lat"], _AXES["lon"] = data["lat"], data["lon"]
        return _AXES["lat"], _AXES["lon"]


def is_land(lats: np.ndarray, lons: np.ndarray) -> np.ndarray:
    """Whether each point is on land (as global_land_mask.globe.is_land)."""
    lat_axis, lon_axis = _axes()
    lats = np.clip(np.asarray(lats, dtype=float), lat_axis.min(), lat_axis.max())
    lons = np.clip(np.asarray(lons, dtype=float), lon_axis.min(), lon_axis.max())
    rows = ((lats - lat_axis[0]) / (lat_axis[1] - lat_axis[0])).astype(int)
    cols = ((lons - lon_axis[0]) / (lon_axis[1] - lon_axis[0])).astype(int)
    rows = np.clip(rows, 0, ROWS - 1)
    cols = np.clip(cols, 0, COLS - 1)
    result = np.ones(rows.shape, dtype=bool)
    band_of = rows // BAND_ROWS
    # The bands in order, as np.unique gives them (which imports numpy.ma, a few ms, for this).
    for band in sorted(set(band_of.tolist())):
        picked = band_of == band
        packed = _band(int(band))[rows[picked] - band * BAND_ROWS, cols[picked] >> 3]
        # np.packbits is big-endian within a byte: cell c is bit 7 - c % 8.
        result[picked] = (packed >> (7 - (cols[picked] & 7))) & 1 == 1
    return ~result  # the package's grid is True at sea
