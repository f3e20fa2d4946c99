"""The global-land-mask data without loading it whole.

The package holds a 21,600 x 43,200 boolean grid (about 1 km cells) that its own module
decompresses into 933 MB at import. Here the grid is streamed once out of the package's npz into
bit-packed bands of BAND_ROWS rows (a few MB in all, in the user cache directory or
COUNTERSIGN_LAND_MASK_CACHE) and each band is loaded when a point falls in it.

The cache is one file: MAGIC, the length of a JSON index (4 bytes, big-endian), the index (the
axes' four numbers each, and each band's offset and length after the index), then the bands,
each its packed bits zlib-compressed. A lookup reads the index and its bands' bytes; an npz
(v2) had each lookup parse a zip directory of 360-odd members and load a codec for their names,
about a tenth of what `countersign validate` spent on land.
"""

from __future__ import annotations

import importlib.util
import json
import os
import tempfile
import threading
import zipfile
import zlib
from pathlib import Path
from typing import Any

import numpy as np
import platformdirs

from ..settings import InstallationEnvironment, read

ROWS, COLS = 21_600, 43_200
# Half a degree of latitude: a band is inflated from the cache when a point falls in it, and a
# band of 600 rows (v1) took about 9 ms of CPU of every `countersign validate`, 60 rows about 1.
BAND_ROWS = 60
PACKED_COLS = (COLS + 7) // 8
CACHE_NAME = "land-mask-v3.bin"
MAGIC = b"countersign-land-mask-v3\n"
_LOCK = threading.Lock()
_ARRAYS: dict[str, np.ndarray] = {}  # the cache's arrays read so far, by name
_INDEX: dict[str, Any] = {}  # the cache's index, once read


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
        # Of the cells' latitudes and longitudes, what a lookup reads: the first two and the
        # least and greatest (the same floats; the axes whole are 0.5 MB to inflate).
        for name in ("lat", "lon"):
            with archive.open(f"{name}.npy") as handle:
                axis = np.lib.format.read_array(handle)
            bands[name] = np.array([axis[0], axis[1], axis.min(), axis.max()])
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
    _write(target, bands)


def _write(target: Path, bands: dict[str, np.ndarray]) -> None:
    """The cache file (see the module's doc) of the axes and the packed bands, written whole
    under another name and then renamed, so that a reader never sees half of it."""
    blobs = [zlib.compress(bands[f"b{band}"].tobytes(), 6) for band in range(ROWS // BAND_ROWS)]
    spans, at = [], 0
    for blob in blobs:
        spans.append([at, len(blob)])
        at += len(blob)
    index = json.dumps({"lat": bands["lat"].tolist(), "lon": bands["lon"].tolist(),
                        "bands": spans}).encode()
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=target.parent, suffix=".bin")
    with os.fdopen(fd, "wb") as out:
        out.write(MAGIC + len(index).to_bytes(4, "big") + index)
        out.writelines(blobs)
    os.replace(tmp, target)


def _read(names: list[str]) -> dict[str, np.ndarray]:
    path = cache_path()
    if not path.exists():
        _build(path)
    with path.open("rb") as handle:
        if not _INDEX:
            if handle.read(len(MAGIC)) != MAGIC:
                raise RuntimeError(f"{path} is not a land mask cache; delete it to rebuild it")
            size = int.from_bytes(handle.read(4), "big")
            _INDEX.update(json.loads(handle.read(size)), start=len(MAGIC) + 4 + size)
        found: dict[str, np.ndarray] = {}
        for name in names:
            if name in ("lat", "lon"):
                found[name] = np.array(_INDEX[name], dtype=float)
                continue
            offset, length = _INDEX["bands"][int(name.removeprefix("b"))]
            handle.seek(_INDEX["start"] + offset)
            bits = np.frombuffer(zlib.decompress(handle.read(length)), dtype=np.uint8)
            found[name] = bits.reshape(BAND_ROWS, PACKED_COLS)
        return found


def _arrays(*names: str) -> list[np.ndarray]:
    """The named arrays of the cache (a band `b<index>`'s bits still packed eight cells to a
    byte: unpacked, a band is 2.6 MB), those not read before read with one opening of it."""
    with _LOCK:
        missing = [name for name in names if name not in _ARRAYS]
        if missing:
            _ARRAYS.update(_read(missing))
        return [_ARRAYS[name] for name in names]


def _axes() -> tuple[np.ndarray, np.ndarray]:
    """Of the latitudes and of the longitudes of the cells: the first, the second, the least
    and the greatest."""
    lat, lon = _arrays("lat", "lon")
    return lat, lon


def is_land(lats: np.ndarray, lons: np.ndarray) -> np.ndarray:
    """Whether each point is on land (as global_land_mask.globe.is_land)."""
    (lat0, lat1, lat_min, lat_max), (lon0, lon1, lon_min, lon_max) = _axes()
    lats = np.clip(np.asarray(lats, dtype=float), lat_min, lat_max)
    lons = np.clip(np.asarray(lons, dtype=float), lon_min, lon_max)
    rows = ((lats - lat0) / (lat1 - lat0)).astype(int)
    cols = ((lons - lon0) / (lon1 - lon0)).astype(int)
    rows = np.clip(rows, 0, ROWS - 1)
    cols = np.clip(cols, 0, COLS - 1)
    result = np.ones(rows.shape, dtype=bool)
    band_of = rows // BAND_ROWS
    # The bands in order, as np.unique gives them (which imports numpy.ma, a few ms, for this).
    bands = sorted(set(band_of.tolist()))
    for band, bits in zip(bands, _arrays(*(f"b{band}" for band in bands)), strict=True):
        picked = band_of == band
        packed = bits[rows[picked] - band * BAND_ROWS, cols[picked] >> 3]
        # np.packbits is big-endian within a byte: cell c is bit 7 - c % 8.
        result[picked] = (packed >> (7 - (cols[picked] & 7))) & 1 == 1
    return ~result  # the package's grid is True at sea
