"""The land mask's cache file holds the package's grid bit for bit, and a lookup reads only
that file (no zip directory to parse: see verify/land_mask.py)."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest

from countersign.verify import land_mask

BAND = 20  # rows 1,200-1,259 from 90° N: Greenland, Svalbard, Franz Josef Land and sea


def _package_band(band: int) -> np.ndarray:
    with zipfile.ZipFile(land_mask._package_file()) as archive, \
            archive.open("mask.npy") as stream:
        version = np.lib.format.read_magic(stream)
        read_header = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                       else np.lib.format.read_array_header_2_0)
        read_header(stream)
        stream.read(band * land_mask.BAND_ROWS * land_mask.COLS)
        raw = stream.read(land_mask.BAND_ROWS * land_mask.COLS)
    return np.frombuffer(raw, dtype=np.uint8).reshape(land_mask.BAND_ROWS, land_mask.COLS)


def test_a_cached_band_is_the_package_grid() -> None:
    packed = land_mask._arrays(f"b{BAND}")[0]
    unpacked = np.unpackbits(packed, axis=1, count=land_mask.COLS)
    package = _package_band(BAND)
    assert np.array_equal(unpacked, package != 0)
    assert 0 < int(package.sum()) < package.size  # land and sea both


def test_a_rebuilt_cache_is_read_without_the_zip(tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    cache = tmp_path / "land.bin"
    monkeypatch.setenv("COUNTERSIGN_LAND_MASK_CACHE", str(cache))
    monkeypatch.setattr(land_mask, "_ARRAYS", {})
    monkeypatch.setattr(land_mask, "_INDEX", {})
    lats, lons = np.array([-35.2, 51.5, -35.2, 0.1]), np.array([149.1, -0.1, -170.0, -160.0])
    built = land_mask.is_land(lats, lons).tolist()  # builds the file from the package
    assert cache.read_bytes().startswith(land_mask.MAGIC)
    monkeypatch.setattr(land_mask, "_ARRAYS", {})
    monkeypatch.setattr(land_mask, "_INDEX", {})

    def no_zip(*_: object, **__: object) -> None:
        raise AssertionError("a lookup opened a zip archive")

    monkeypatch.setattr(zipfile, "ZipFile", no_zip)
    assert land_mask.is_land(lats, lons).tolist() == built == [True, True, False, False]
