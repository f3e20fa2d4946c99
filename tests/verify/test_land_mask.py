"""The land mask is read from bit-packed bands without unpacking them (a
whole band unpacked is 2.6 MB, the grid 933 MB). Each looked-up cell is the cell of the
unpacked grid, found with the package's own axes."""

from __future__ import annotations

import zipfile

import numpy as np

from countersign.verify import land_mask


def _package_axes() -> tuple[np.ndarray, np.ndarray]:
    with zipfile.ZipFile(land_mask._package_file()) as archive:
        axes = []
        for name in ("lat", "lon"):
            with archive.open(f"{name}.npy") as handle:
                axes.append(np.lib.format.read_array(handle))
    return axes[0], axes[1]


def test_the_cache_keeps_what_a_lookup_reads_of_the_axes() -> None:
    lat_axis, lon_axis = _package_axes()
    lat, lon = land_mask._axes()
    for kept, axis in ((lat, lat_axis), (lon, lon_axis)):
        assert kept.tolist() == [axis[0], axis[1], axis.min(), axis.max()]


def test_packed_lookup_is_the_unpacked_cell() -> None:
    rng = np.random.default_rng(17)
    lat_axis, lon_axis = _package_axes()
    band = 35 * 120 // land_mask.BAND_ROWS + 90 * 120 // land_mask.BAND_ROWS  # from 35° S:
    # Argentina, Uruguay, Australia and ocean (a cell is 1/120 degree, row 0 at 90° N)
    lats = rng.uniform(lat_axis[(band + 1) * land_mask.BAND_ROWS - 1],
                       lat_axis[band * land_mask.BAND_ROWS], 5_000)
    lons = rng.uniform(-180.0, 180.0, 5_000)
    land = land_mask.is_land(lats, lons)
    packed = land_mask._arrays(f"b{band}")[0]
    unpacked = np.unpackbits(packed, axis=1, count=land_mask.COLS).astype(bool)
    rows = ((lats - lat_axis[0]) / (lat_axis[1] - lat_axis[0])).astype(int) \
        - band * land_mask.BAND_ROWS
    cols = np.clip(((lons - lon_axis[0]) / (lon_axis[1] - lon_axis[0])).astype(int),
                   0, land_mask.COLS - 1)
    assert np.array_equal(land, ~unpacked[rows, cols])
    assert 0 < int(land.sum()) < len(land)  # both land and sea were looked up


def test_points_in_several_bands_are_each_looked_up_in_their_own() -> None:
    # One call reads all its bands at once: each point still reads its own band's cell.
    lats = np.array([-35.2, 51.5, -35.2, 0.1, 89.9, -89.9])
    lons = np.array([149.1, -0.1, -170.0, -160.0, 0.0, 0.0])
    together = land_mask.is_land(lats, lons)
    alone = [bool(land_mask.is_land(lats[i:i + 1], lons[i:i + 1])[0]) for i in range(len(lats))]
    assert together.tolist() == alone
    assert together.tolist()[:4] == [True, True, False, False]  # Canberra, London, two seas
