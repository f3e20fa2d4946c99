"""The chart registry: shared areas (protected areas, lanes, keep-out zones, anchorages)."""

from __future__ import annotations

from collections.abc import Iterable

from pydantic import TypeAdapter, ValidationError
from sqlalchemy import select
from sqlalchemy.orm import Session

from ..orders.model import Chart, Orders
from ..verify.charts import Box, box_of, with_charts
from .tables import ChartRecord, utcnow

MAX_CHARTS_IN_USE = 5_000


def _chart(row: ChartRecord) -> Chart | None:
    try:
        return Chart.model_validate(row.chart)
    except ValidationError:
        return None  # a row a database writer broke is no chart


def all_charts(db: Session) -> list[Chart]:
    stored = list(db.scalars(select(ChartRecord.chart).order_by(ChartRecord.id)))
    try:
        # One pydantic call for the registry (10,000 charts one by one took seconds).
        return _CHARTS.validate_python(stored)
    except ValidationError:
        return [c for c in map(_chart_of, stored) if c is not None]


_CHARTS = TypeAdapter(list[Chart])


def _chart_of(data: object) -> Chart | None:
    try:
        return Chart.model_validate(data)
    except ValidationError:
        return None  # a row a database writer broke is no chart


def charts_in(db: Session, region: Box) -> list[Chart]:
    south, west, north, east = region
    rows = db.scalars(
        select(ChartRecord)
        .where(ChartRecord.north >= south, ChartRecord.south <= north,
               ChartRecord.east >= west, ChartRecord.west <= east)
        .order_by(ChartRecord.id).limit(MAX_CHARTS_IN_USE))
    return [c for c in map(_chart, rows) if c is not None]


def save_charts(db: Session, charts: Iterable[Chart]) -> list[str]:
    """Insert or replace charts by id; the ids saved, in order."""
    saved = []
    for chart in charts:
        box = box_of(chart.polygon)
        if box is None:
            raise ValueError(f"chart {chart.id} has no polygon")
        data = chart.model_dump(mode="json", exclude_unset=True)
        data["id"] = chart.id
        row = db.get(ChartRecord, chart.id)
        if row is None:
            row = ChartRecord(id=chart.id)
            db.add(row)
        row.title, row.kind, row.chart = chart.title, chart.kind, data
        row.updated_at = utcnow()
        row.south, row.west, row.north, row.east = box
        saved.append(chart.id)
    db.flush()
    return saved


def delete_chart(db: Session, chart_id: str) -> bool:
    row = db.get(ChartRecord, chart_id)
    if row is None:
        return False
    db.delete(row)
    return True


def with_registry_charts(db: Session, orders: Orders) -> Orders:
    return with_charts(orders, lambda region: charts_in(db, region))
