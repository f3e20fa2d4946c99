"""Charted areas from GeoJSON and KML, and areas written back as GeoJSON (or KML).

Polygons in the orders are one ring of (latitude, longitude) without the closing point, wound
either way; GeoJSON and KML write (longitude, latitude) rings that repeat the first point and
run counterclockwise, as RFC 7946 3.1.6 requires of GeoJSON exteriors and OGC KML 2.2 of outer
boundaries. Holes cannot be expressed in the orders, so a polygon with holes is refused rather
than silently filled.
KML is parsed by defusedxml first: a document with a DTD or entities never reaches fastkml.
"""

from __future__ import annotations

import json
import re
import warnings
from collections.abc import Iterable, Sequence
from typing import Any

import defusedxml.ElementTree as SafeET
import shapely
from defusedxml import DefusedXmlException
from geojson_pydantic import Feature, FeatureCollection
from geojson_pydantic import MultiPolygon as GeoMultiPolygon
from geojson_pydantic import Polygon as GeoPolygon
from geojson_pydantic.geometries import Geometry
from pydantic import TypeAdapter, ValidationError
from pygeoif import geometry as pygeo

from .. import strict_json
from .model import Area, Chart, ChartNorm

with warnings.catch_warnings():
    # fastkml warns at import that lxml is absent; the standard library parser is what we want.
    warnings.simplefilter("ignore")
    from fastkml import containers, data, features, kml

MAX_BYTES = 5_000_000
KML_MEDIA_TYPE = "application/vnd.google-earth.kml+xml"
MAX_FEATURES = 10_000
# Every part becomes a chart copied into nearby drafts: bound what one import can add.
MAX_PARTS = 1_000
MAX_VERTICES = 100_000
_SAFE_ID = re.compile(r"[^A-Za-z0-9_.:\-]+")


class GeoFormatError(ValueError):
    """Input that is not a set of charts; the message names what and where."""


def _ring_to_polygon(ring: Sequence[Sequence[float]], where: str) -> list[tuple[float, float]]:
    points = [(float(p[1]), float(p[0])) for p in ring]
    if len(points) >= 2 and points[0] == points[-1]:
        points.pop()
    if len(points) < 3:
        raise GeoFormatError(f"{where}: a polygon needs at least three distinct points")
    return points


def _closed_ring(polygon: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    return _closed_rings([polygon])[0]


def _closed_rings(polygons: Sequence[Sequence[tuple[float, float]]]
                  ) -> list[list[tuple[float, float]]]:
    """Each polygon as a closed counterclockwise (longitude, latitude) ring. The orientation
    of all of them is one vectorised shapely call: one LinearRing object per chart made a
    10,000-chart export take seconds."""
    rings = [[(lon, lat) for lat, lon in polygon] for polygon in polygons]
    testable = [n for n, ring in enumerate(rings) if len(ring) >= 3]
    if testable:
        coordinates = [point for n in testable for point in rings[n]]
        owners = [k for k, n in enumerate(testable) for _ in rings[n]]
        counterclockwise = shapely.is_ccw(shapely.linearrings(coordinates, indices=owners))
        for n, ccw in zip(testable, counterclockwise.tolist(), strict=True):
            if not ccw:
                ring = rings[n]
                rings[n] = [ring[0], *reversed(ring[1:])]  # same first point, other way round
    return [[*ring, ring[0]] if ring else ring for ring in rings]


def _words(value: Any, where: str, name: str) -> list[str]:
    if value is None:
        return []
    if isinstance(value, str):
        return [w.strip() for w in value.split(",") if w.strip()]
    if isinstance(value, list) and all(isinstance(w, str) for w in value):
        return [w.strip() for w in value if w.strip()]
    raise GeoFormatError(f"{where}: {name!r} must be a list of strings or a comma list")


def _behaviour_norms(behaviours: Iterable[str]) -> list[dict[str, str]]:
    norms = []
    for behaviour in behaviours:
        if not re.fullmatch(r"[A-Za-z0-9_]+", behaviour):
            raise GeoFormatError(f"{behaviour[:40]!r} is not a behaviour name")
        norms.append({"id": f"no-{behaviour}", "forbidden": f"behavior == '{behaviour}'",
                      "text": f"No {behaviour.replace('_', ' ')}"})
    return norms


def _chart(raw_id: Any, props: dict[str, Any], polygon: list[tuple[float, float]],
           where: str) -> Chart:
    title = props.get("title", props.get("name", ""))
    chart_id = str(raw_id) if raw_id not in (None, "") else _SAFE_ID.sub("-", str(title)).strip("-")
    if not chart_id:
        raise GeoFormatError(f"{where}: the feature has neither an id nor a name")
    norms = props.get("norms") or []
    if isinstance(norms, str):  # KML ExtendedData holds text only
        try:
            norms = strict_json.loads(norms)
        except strict_json.JsonPolicyError:
            raise GeoFormatError(f"{where}: 'norms' is not a JSON list") from None
    if not isinstance(norms, list):
        raise GeoFormatError(f"{where}: 'norms' must be a list")
    norms = [*norms, *_behaviour_norms(_words(props.get("forbids"), where, "forbids"))]
    fields: dict[str, Any] = {
        "id": chart_id, "title": title if isinstance(title, str) else str(title),
        "polygon": polygon, "contexts": _words(props.get("contexts"), where, "contexts"),
        "norms": norms,
    }
    if props.get("kind") is not None:
        fields["kind"] = props["kind"]
    try:
        return Chart.model_validate(fields)
    except ValidationError as exc:
        first = exc.errors()[0]
        at = ".".join(str(p) for p in first["loc"])
        raise GeoFormatError(f"{where}: {at}: {first['msg']}") from None


def _polygons_of(geometry: Any, where: str) -> list[list[tuple[float, float]]]:
    if isinstance(geometry, GeoPolygon):
        rings = [geometry.coordinates]
    elif isinstance(geometry, GeoMultiPolygon):
        rings = list(geometry.coordinates)
    else:
        kind = type(geometry).__name__ if geometry is not None else "no geometry"
        raise GeoFormatError(f"{where}: a chart must be a Polygon or MultiPolygon, not {kind}")
    if not rings:
        raise GeoFormatError(f"{where}: no polygon in the {type(geometry).__name__}")
    result = []
    for index, polygon in enumerate(rings):
        if not polygon:
            raise GeoFormatError(f"{where}: polygon {index} has no ring")
        if len(polygon) > 1:
            raise GeoFormatError(f"{where}: polygon {index} has holes, which orders cannot hold")
        result.append(_ring_to_polygon([tuple(p) for p in polygon[0]], where))
    return result


def _split(base: Chart, polygons: list[list[tuple[float, float]]]) -> list[Chart]:
    if len(polygons) == 1:
        return [base.model_copy(update={"polygon": polygons[0]})]
    return [base.model_copy(update={"id": f"{base.id}-{n + 1}", "polygon": p})
            for n, p in enumerate(polygons)]


def _bounded(text: str | bytes) -> str:
    if len(text) > MAX_BYTES:
        raise GeoFormatError(f"the file has more than {MAX_BYTES:,} bytes")
    if isinstance(text, bytes):
        try:
            return text.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise GeoFormatError(f"the file is not UTF-8 (byte {exc.start})") from None
    return text


def charts_from_geojson(text: str | bytes) -> list[Chart]:
    """Charts from a GeoJSON FeatureCollection (or one Feature) of polygons."""
    source = _bounded(text)
    try:
        raw = strict_json.loads(source)
    except strict_json.JsonPolicyError as exc:
        raise GeoFormatError(f"not JSON: {exc.message} (at {exc.path})") from None
    if isinstance(raw, dict) and raw.get("type") == "Feature":
        raw = {"type": "FeatureCollection", "features": [raw]}
    if not isinstance(raw, dict) or raw.get("type") != "FeatureCollection":
        raise GeoFormatError("GeoJSON charts must be a FeatureCollection or a Feature")
    if len(raw.get("features") or []) > MAX_FEATURES:
        raise GeoFormatError(f"more than {MAX_FEATURES:,} features")
    try:
        collection = FeatureCollection[Feature[Geometry, dict[str, Any]]].model_validate(raw)
    except ValidationError as exc:
        first = exc.errors()[0]
        at = ".".join(str(p) for p in first["loc"])
        raise GeoFormatError(f"not GeoJSON: {at}: {first['msg']}") from None
    charts: list[Chart] = []
    for index, feature in enumerate(collection.features):
        where = f"feature {index}"
        props = dict(feature.properties or {})
        polygons = _polygons_of(feature.geometry, where)
        base = _chart(feature.id if feature.id is not None else props.get("id"), props,
                      polygons[0], where)
        charts.extend(_split(base, polygons))
        _check_size(charts)
    return _unique(charts)


def _check_size(charts: list[Chart]) -> None:
    if len(charts) > MAX_PARTS:
        raise GeoFormatError(f"more than {MAX_PARTS:,} polygons (parts) in one import")
    if sum(len(chart.polygon) for chart in charts) > MAX_VERTICES:
        raise GeoFormatError(f"more than {MAX_VERTICES:,} vertices in one import")


def _unique(charts: list[Chart]) -> list[Chart]:
    seen: set[str] = set()
    for chart in charts:
        if chart.id in seen:
            raise GeoFormatError(f"two charts share the id {chart.id!r}")
        seen.add(chart.id)
    return charts


_NORMS = TypeAdapter(list[list[ChartNorm]])


def areas_to_geojson(areas: Iterable[Area]) -> dict[str, Any]:
    """A FeatureCollection with one Polygon feature per area (charts keep kind and norms).
    Plain dicts, not geojson-pydantic models: what it writes is checked by geojson-validator
    in tests/orders/test_geo_formats_out.py, and models cost seconds at 10,000 charts."""
    areas = list(areas)
    rings = _closed_rings([area.polygon for area in areas])
    # Every chart's norms in one pydantic call: one call per chart cost more than the rest.
    norms = iter(_NORMS.dump_python([a.norms for a in areas if isinstance(a, Chart)],
                                    mode="json"))
    feats = []
    for area, ring in zip(areas, rings, strict=True):
        props: dict[str, Any] = {"title": area.title, "contexts": list(area.contexts)}
        if isinstance(area, Chart):
            props["kind"] = area.kind
            props["norms"] = next(norms)
        feats.append({"type": "Feature", "id": area.id, "properties": props,
                      "geometry": {"type": "Polygon",
                                   "coordinates": [[list(point) for point in ring]]}})
    return {"type": "FeatureCollection", "features": feats}


# KML ---------------------------------------------------------------------------------------


def _placemarks(feature: Any) -> Iterable[Any]:
    if isinstance(feature, features.Placemark):
        yield feature
    elif isinstance(feature, containers.Document | containers.Folder):
        for child in feature.features:
            yield from _placemarks(child)


def _kml_polygons(geometry: Any, where: str) -> list[list[tuple[float, float]]]:
    if isinstance(geometry, pygeo.Polygon):
        shapes = [geometry]
    elif isinstance(geometry, pygeo.MultiPolygon):
        shapes = list(geometry.geoms)
    else:
        kind = type(geometry).__name__ if geometry is not None else "no geometry"
        raise GeoFormatError(f"{where}: a chart must be a Polygon, not {kind}")
    result = []
    for index, shape in enumerate(shapes):
        if list(shape.interiors):
            raise GeoFormatError(f"{where}: polygon {index} has holes, which orders cannot hold")
        result.append(_ring_to_polygon(list(shape.exterior.coords), where))
    return result


def charts_from_kml(text: str | bytes) -> list[Chart]:
    """Charts from the Polygon placemarks of a KML document; ExtendedData `kind`, `contexts`
    and `forbids` (comma lists) carry what KML has no element for."""
    source = _bounded(text)
    try:
        tree = SafeET.fromstring(source)  # refuses DTDs and entities before they expand
    except DefusedXmlException as exc:
        raise GeoFormatError(f"KML refused: {type(exc).__name__} (no DTD or entities)") from None
    except SafeET.ParseError as exc:
        raise GeoFormatError(f"not XML: {exc}") from None
    _check_kml_size(tree)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            document = kml.KML.from_string(source, strict=False)
    except Exception as exc:  # fastkml raises many kinds for malformed KML
        raise GeoFormatError(f"not KML: {str(exc)[:200]}") from None
    charts: list[Chart] = []
    index = 0
    for top in document.features:
        for placemark in _placemarks(top):
            where = f"placemark {index}" + (f" ({placemark.name})" if placemark.name else "")
            index += 1
            if index > MAX_FEATURES:
                raise GeoFormatError(f"more than {MAX_FEATURES:,} placemarks")
            props: dict[str, Any] = {"name": placemark.name or ""}
            if placemark.extended_data is not None:
                for element in placemark.extended_data.elements:
                    if isinstance(element, data.Data) and element.name:
                        props[element.name] = element.value
            polygons = _kml_polygons(placemark.geometry, where)
            charts.extend(_split(_chart(placemark.id, props, polygons[0], where), polygons))
    return _unique(charts)


def _check_kml_size(tree: Any) -> None:
    """GeoJSON's bounds (MAX_PARTS polygons, MAX_VERTICES vertices), counted on the plain XML
    tree before fastkml builds an object per placemark (10,000 placemarks became
    10,000 charts copied into every nearby draft)."""
    polygons = vertices = 0
    for element in tree.iter():
        name = element.tag.rsplit("}", 1)[-1] if isinstance(element.tag, str) else ""
        if name == "Polygon":
            polygons += 1
            if polygons > MAX_PARTS:
                raise GeoFormatError(f"more than {MAX_PARTS:,} polygons (parts) in one import")
        elif name == "coordinates":
            vertices += len((element.text or "").split())
            if vertices > MAX_VERTICES:
                raise GeoFormatError(f"more than {MAX_VERTICES:,} vertices in one import")


def charts_to_kml(charts: Iterable[Area]) -> str:
    """A KML document with one Polygon placemark per area, the rings of areas_to_geojson
    (round-trips with charts_from_kml). Titles and tags are element text, escaped on writing."""
    marks = []
    for area in charts:
        extra = [data.Data(name="contexts", value=",".join(area.contexts))]
        if isinstance(area, Chart):
            extra.append(data.Data(name="kind", value=area.kind))
            if area.norms:
                norms = [n.model_dump(mode="json") for n in area.norms]
                extra.append(data.Data(name="norms", value=json.dumps(norms)))
        marks.append(features.Placemark(
            id=area.id, name=area.title or area.id,
            geometry=pygeo.Polygon(_closed_ring(area.polygon)),
            extended_data=data.ExtendedData(elements=extra),
        ))
    document = kml.KML(features=[containers.Document(features=marks)])
    return str(document.to_string())


def read_charts(name: str, content: bytes) -> list[Chart]:
    """Charts from a file by its extension: .geojson/.json or .kml."""
    lower = name.lower()
    if lower.endswith(".kml"):
        return charts_from_kml(content)
    if lower.endswith((".geojson", ".json")):
        return charts_from_geojson(content)
    raise GeoFormatError(f"{name}: charts are read from .geojson, .json or .kml files")
