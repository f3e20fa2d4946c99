"""Land from the bundled global land mask (global-land-mask, about 1 km cells).

Legs are sampled every SAMPLE_M metres; the first and last LAND_MARGIN_M are not, because goals
near a harbour start and end within a cell of the coast and the mask cannot resolve a quay.
The mask's cells are about 1 km, so a point counts as land only when the mask is land at it and
LAND_SURE_M around it in eight directions: a leg that hugs a coast or a narrow mole is not
reported, a leg across a headland or a coast is. The coastline for the plan view is the
boundary between land and sea cells of a coarse grid.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from shapely.geometry import LineString

from . import land_mask
from .legs import Frame

SAMPLE_M = 1_000.0  # land that counts is 2 km across (LAND_SURE_M each way): a sample lands in it
LAND_MARGIN_M = 600.0
MAX_SAMPLES_PER_LINE = 4_000
MAX_COAST_CELLS = 200
LAND_SURE_M = 1_000.0
_METRES_PER_DEGREE = 111_320.0


def is_land(lats: np.ndarray, lons: np.ndarray) -> np.ndarray:
    lats = np.clip(lats, -89.999, 89.999)
    lons = ((lons + 180.0) % 360.0) - 180.0
    return land_mask.is_land(lats, lons)


def surely_land(lats: np.ndarray, lons: np.ndarray) -> np.ndarray:
    """Land at each point and LAND_SURE_M away from it in the eight compass directions."""
    dlat = LAND_SURE_M / _METRES_PER_DEGREE
    dlon = dlat / np.maximum(np.cos(np.radians(lats)), 0.01)
    sure = is_land(lats, lons)
    for ky in (-1, 0, 1):
        for kx in (-1, 0, 1):
            if (ky or kx) and sure.any():
                sure &= is_land(lats + ky * dlat, lons + kx * dlon)
    return sure


def _samples(line: LineString) -> np.ndarray:
    """Points every SAMPLE_M along the line, leaving out LAND_MARGIN_M at either end."""
    coords = np.asarray(line.coords, dtype=float)[:, :2]
    steps = np.hypot(*np.diff(coords, axis=0).T)
    along = np.concatenate([[0.0], np.cumsum(steps)])
    usable = along[-1] - 2 * LAND_MARGIN_M
    if usable <= 0:
        return np.empty((0, 2))
    step = max(SAMPLE_M, usable / MAX_SAMPLES_PER_LINE)
    distances = LAND_MARGIN_M + np.arange(0.0, usable + 1e-9, step)
    return np.column_stack([np.interp(distances, along, coords[:, 0]),
                            np.interp(distances, along, coords[:, 1])])


def land_hits(frame: Frame, lines: Sequence[LineString]) -> list[tuple[float, float] | None]:
    """Per line, the first sampled point on land (lat, lon), or None."""
    owners: list[np.ndarray] = []
    points: list[np.ndarray] = []
    for i, line in enumerate(lines):
        sampled = _samples(line)
        if len(sampled):
            points.append(sampled)
            owners.append(np.full(len(sampled), i))
    result: list[tuple[float, float] | None] = [None] * len(lines)
    if not points:
        return result
    flat = np.concatenate(points)
    owner = np.concatenate(owners)
    lats, lons = frame.to_latlon(flat[:, 0], flat[:, 1])
    land = surely_land(lats, lons)
    for k in np.flatnonzero(land).tolist():
        i = int(owner[k])
        if result[i] is None:
            result[i] = (round(float(lats[k]), 6), round(float(lons[k]), 6))
    return result


def coastline(south: float, west: float, north: float, east: float,
              cells: int = 120) -> list[list[tuple[float, float]]]:
    """Segments [(lat, lon), (lat, lon)] between land and sea cells of a grid over the box."""
    cells = max(2, min(cells, MAX_COAST_CELLS))
    lat_edges = np.linspace(south, north, cells + 1)
    lon_edges = np.linspace(west, east, cells + 1)
    lat_mid = (lat_edges[:-1] + lat_edges[1:]) / 2
    lon_mid = (lon_edges[:-1] + lon_edges[1:]) / 2
    grid_lat, grid_lon = np.meshgrid(lat_mid, lon_mid, indexing="ij")
    land = is_land(grid_lat.ravel(), grid_lon.ravel()).reshape(cells, cells)
    segments: list[list[tuple[float, float]]] = []
    rows, cols = np.nonzero(land[:, 1:] != land[:, :-1])  # vertical boundaries
    for r, c in zip(rows.tolist(), cols.tolist(), strict=True):
        lon = float(lon_edges[c + 1])
        segments.append([(float(lat_edges[r]), lon), (float(lat_edges[r + 1]), lon)])
    rows, cols = np.nonzero(land[1:, :] != land[:-1, :])  # horizontal boundaries
    for r, c in zip(rows.tolist(), cols.tolist(), strict=True):
        lat = float(lat_edges[r + 1])
        segments.append([(lat, float(lon_edges[c])), (lat, float(lon_edges[c + 1]))])
    return segments
