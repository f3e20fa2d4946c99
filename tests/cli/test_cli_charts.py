"""`countersign charts`: check a file offline, import into the registry, list, delete."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from countersign.cli import main

CHART = {"type": "FeatureCollection", "features": [{
    "type": "Feature", "id": "RANGE",
    "properties": {"title": "Firing range", "kind": "keep_out", "forbids": ["transit"]},
    "geometry": {"type": "Polygon", "coordinates": [[[-121.845, 36.75], [-121.825, 36.75],
                                                     [-121.825, 36.77], [-121.845, 36.75]]]}}]}


def test_import_list_delete(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                            monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("COUNTERSIGN_DATABASE_URL", raising=False)
    source = tmp_path / "range.geojson"
    source.write_text(json.dumps(CHART))
    data = str(tmp_path / "data")
    assert main(["charts", "check", str(source)]) == 0
    assert "RANGE\tkeep_out" in capsys.readouterr().out
    assert main(["charts", "import", str(source), "--data-dir", data]) == 0
    assert main(["charts", "list", "--format", "geojson", "--data-dir", data]) == 0
    out = capsys.readouterr().out
    exported = json.loads(out[out.index("{"):])
    assert exported["features"][0]["id"] == "RANGE"
    assert exported["features"][0]["properties"]["norms"][0]["forbidden"] == \
        "behavior == 'transit'"
    assert main(["charts", "delete", "RANGE", "--data-dir", data]) == 0
    assert main(["charts", "delete", "RANGE", "--data-dir", data]) == 2


def test_unreadable_chart_file_is_exit_2(tmp_path: Path,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.kml"
    bad.write_text('<!DOCTYPE kml [<!ENTITY a "b">]><kml>&a;</kml>')
    assert main(["charts", "check", str(bad)]) == 2
    assert "EntitiesForbidden" in capsys.readouterr().err
    assert main(["charts", "check", str(tmp_path / "missing.geojson")]) == 2
    other = tmp_path / "charts.shp"
    other.write_bytes(b"\0")
    assert main(["charts", "check", str(other)]) == 2


def test_list_writes_rfc_7946_geojson_and_the_same_rings_as_kml(
        tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    import warnings

    from shapely.geometry import LinearRing

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # fastkml's notice that lxml is absent
        from fastkml import kml

    monkeypatch.delenv("COUNTERSIGN_DATABASE_URL", raising=False)
    clockwise = json.loads(json.dumps(CHART))
    ring = [[-121.845, 36.75], [-121.845, 36.77], [-121.825, 36.77], [-121.825, 36.75],
            [-121.845, 36.75]]
    assert not LinearRing(ring).is_ccw
    clockwise["features"][0]["geometry"]["coordinates"] = [ring]
    clockwise["features"][0]["properties"]["title"] = "Range <b>&amp;</b>"
    source = tmp_path / "range.geojson"
    source.write_text(json.dumps(clockwise))
    data = str(tmp_path / "data")
    assert main(["charts", "import", str(source), "--data-dir", data]) == 0
    capsys.readouterr()
    assert main(["charts", "list", "--format", "geojson", "--data-dir", data]) == 0
    out = json.loads(capsys.readouterr().out)["features"][0]["geometry"]["coordinates"][0]
    assert LinearRing(out).is_ccw and out[0] == ring[0] and out[-1] == out[0]
    assert main(["charts", "list", "--format", "kml", "--data-dir", data]) == 0
    text = capsys.readouterr().out
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (mark,) = kml.KML.from_string(text, strict=True).features[0].features
    assert mark.id == "RANGE" and mark.name == "Range <b>&amp;</b>"
    assert [list(p) for p in mark.geometry.exterior.coords] == out
