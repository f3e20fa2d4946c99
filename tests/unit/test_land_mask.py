"""The land mask is read from bit-packed bands without unpacking them (a
whole band unpacked is 26 MB and most of `countersign validate`'s geo check). Each looked-up
cell is the cell of the unpacked grid."""

from __future__ import annotations

import numpy as np

from countersign.verify import land_mask


def test_packed_lookup_is_the_unpacked_cell() -> None:
    rng = np.random.default_rng(17)
    lat_axis, lon_axis = land_mask._axes()
    band = 25  # 35-40 degrees south: Argentina, Australia, New Zealand and ocean
    lats = rng.uniform(lat_axis[(band + 1) * land_mask.BAND_ROWS - 1],
                       lat_axis[band * land_mask.BAND_ROWS], 5_000)
    lons = rng.uniform(-180.0, 180.0, 5_000)
    land = land_mask.is_land(lats, lons)
    unpacked = np.unpackbits(land_mask._band(band), axis=1, count=land_mask.COLS).astype(bool)
    rows = ((lats - lat_axis[0]) / (lat_axis[1] - lat_axis[0])).astype(int) - band * 600
    cols = np.clip(((lons - lon_axis[0]) / (lon_axis[1] - lon_axis[0])).astype(int),
                   0, land_mask.COLS - 1)
    assert np.array_equal(land, ~unpacked[rows, cols])
    assert 0 < int(land.sum()) < len(land)  # both land and sea were looked up
