"""JSON nested a thousand deep, sent where users send JSON, is refused as not JSON by the one
JSON policy (strict_json) with a clear message, never a RecursionError: GeoJSON charts, the
norms of a chart's feature, and the bundle and checkpoints `countersign audit verify` reads."""

from __future__ import annotations

from pathlib import Path

import pytest

from countersign.cli import main
from countersign.orders.geo_formats import GeoFormatError, charts_from_geojson

DEEP = "[" * 1000 + "]" * 1000


def test_a_geojson_chart_nested_too_deep_is_not_json() -> None:
    with pytest.raises(GeoFormatError, match=r"not JSON: .*nested"):
        charts_from_geojson('{"type": "FeatureCollection", "features": ' + DEEP + "}")


def test_norms_nested_too_deep_are_not_a_json_list() -> None:
    feature = ('{"type": "Feature", "id": "a", "properties": {"norms": "' + DEEP + '"},'
               ' "geometry": {"type": "Polygon", "coordinates": [[[0,0],[1,0],[1,1],[0,0]]]}}')
    with pytest.raises(GeoFormatError, match="'norms' is not a JSON list"):
        charts_from_geojson(feature)


@pytest.mark.parametrize("which", ["bundle", "checkpoint"])
def test_audit_verify_refuses_deep_json_with_exit_2(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], which: str) -> None:
    bundle, checkpoint = tmp_path / "bundle.json", tmp_path / "checkpoint.json"
    bundle.write_text(DEEP if which == "bundle" else "{}")
    checkpoint.write_text(DEEP)
    assert main(["audit", "verify", str(bundle), "--checkpoint", str(checkpoint)]) == 2
    assert "nested" in capsys.readouterr().err
