"""Benchmark of: `GET /api/charts/geojson` with 10,000 charts in the registry
(put there by a database writer: imports stop at the registry's bound), through the app,
beside the export it replaced (every row validated as a Chart, each feature built as a
geojson-pydantic model, then dumped) measured in this same process.

Run: .venv/bin/python -m tests.bench.bench_charts_export [--charts 10000]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from fastapi.testclient import TestClient
from geojson_pydantic import Feature, FeatureCollection
from geojson_pydantic import Polygon as GeoPolygon
from shapely.geometry import LinearRing

from countersign.orders.geo_formats import areas_to_geojson
from countersign.orders.model import Chart
from countersign.settings import Settings
from countersign.store.accounts import create_token, create_user
from countersign.store.charts import all_charts
from countersign.store.db import Database
from countersign.store.tables import ChartRecord
from countersign.web.app import create_app


def _fill(database: Database, count: int) -> None:
    with database.session() as db:
        for n in range(count):
            lat, lon = 34 + (n % 100) * 0.01, -126 + (n // 100) * 0.01
            ring = [[lat, lon], [lat, lon + 0.005], [lat + 0.005, lon + 0.005]]
            db.add(ChartRecord(id=f"C{n:05d}", title=f"chart {n}", kind="keep_out",
                               chart={"id": f"C{n:05d}", "title": f"chart {n}",
                                      "kind": "keep_out", "polygon": ring,
                                      "norms": [{"id": "N1", "forbidden": "behavior == 'sample'"}]},
                               south=lat, west=lon, north=lat + 0.005, east=lon + 0.005))


def replaced_export(charts: list[Chart]) -> dict[str, Any]:
    """The export before: a LinearRing per chart for its orientation, a
    geojson-pydantic Feature per chart, then a dump of the whole collection."""
    feats = []
    for chart in charts:
        ring = [(lon, lat) for lat, lon in chart.polygon]
        if len(ring) >= 3 and not LinearRing(ring).is_ccw:
            ring = [ring[0], *reversed(ring[1:])]
        props: dict[str, Any] = {"title": chart.title, "contexts": list(chart.contexts),
                                 "kind": chart.kind,
                                 "norms": [n.model_dump(mode="json") for n in chart.norms]}
        feats.append(Feature[GeoPolygon, dict[str, Any]](
            type="Feature", id=chart.id, properties=props,
            geometry=GeoPolygon(type="Polygon", coordinates=[[*ring, ring[0]]])))
    collection = FeatureCollection[Feature[GeoPolygon, dict[str, Any]]](
        type="FeatureCollection", features=feats)
    return collection.model_dump(mode="json", exclude_none=True)


def _best(action: Callable[[], object], rounds: int = 3) -> float:
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--charts", type=int, default=10_000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        url = f"sqlite:///{Path(tmp) / 'bench.db'}"
        database = Database(url)
        app = create_app(Settings(data_dir=Path(tmp), database_url=url), database)
        with database.session() as db:
            user = create_user(db, username="auditor1", role="auditor",
                               password="correct horse battery staple", signer=database.log_signer)
            token = create_token(db, user=user, name="bench", signer=database.log_signer)[1]
        _fill(database, args.charts)
        client = TestClient(app)
        client.headers["Authorization"] = f"Bearer {token}"

        def route() -> None:
            response = client.get("/api/charts/geojson")
            assert response.status_code == 200, response.text
            assert response.content.count(b'"Feature"') == args.charts

        def replaced() -> None:
            with database.session(write=False) as db:
                charts = all_charts(db)
            assert replaced_export(charts) == areas_to_geojson(charts)  # the same document

        def export_now() -> None:
            with database.session(write=False) as db:
                areas_to_geojson(all_charts(db))

        whole, now, before = _best(route), _best(export_now), _best(replaced)
        print(f"GET /api/charts/geojson, {args.charts} charts: {whole:.2f} s through the app; "
              f"the export {now:.2f} s beside the replaced one {before:.2f} s: "
              f"ratio {before / now:.1f}x")
        database.engine.dispose()


if __name__ == "__main__":
    main()
