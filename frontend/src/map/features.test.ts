import { describe, expect, it } from "vitest";

import { areaCollection, areaStyle, boundsOf, findAreas, graticule, graticuleStep, legCollection, lonLat, type MapArea } from "./features";

const area = (id: string, polygon: number[][], extra: Partial<MapArea> = {}): MapArea => ({
  id,
  source: "area",
  style: "area",
  polygon,
  ...extra,
});

describe("chart geometry", () => {
  it("writes GeoJSON as (longitude, latitude) from the orders' (latitude, longitude)", () => {
    expect(lonLat([36.7, -121.9])).toEqual([-121.9, 36.7]);
    expect(lonLat([Number.NaN, 1])).toBeNull();
  });

  it("closes a ring and draws two vertices as a line so a new area shows at once", () => {
    const fc = areaCollection([
      area("A", [[36.7, -121.9], [36.7, -121.87], [36.695, -121.87]]),
      area("B", [[36.0, -121.0], [36.1, -121.0]]),
      area("C", [[36.0, -121.0]]),
    ]);
    expect(fc.features).toHaveLength(2);
    const ring = (fc.features[0]!.geometry as { coordinates: number[][][] }).coordinates[0]!;
    expect(ring[0]).toEqual([-121.9, 36.7]);
    expect(ring[ring.length - 1]).toEqual(ring[0]);
    expect((fc.features[1]!.geometry as { type: string }).type).toBe("LineString");
  });

  it("styles keep-out, land and protected areas apart, the strongest restriction first", () => {
    expect(areaStyle(["coastal"])).toBe("area");
    expect(areaStyle(["marine_protected_area"])).toBe("protected");
    expect(areaStyle(["shipping_lane", "keep_out"])).toBe("keep_out");
    expect(areaStyle(["land", "protected_area"])).toBe("land");
    expect(areaStyle([null, "traffic_separation"])).toBe("lane");
  });

  it("draws a leg per outcome edge with both ends known", () => {
    const fc = legCollection([
      { goal: "G1", outcome: "succeed", to: "G2", start: [36.7, -121.9], end: [36.8, -121.8], crossed: false },
      { goal: "G1", outcome: "fail", to: "G3", start: [36.7, -121.9], end: [Number.NaN, 0], crossed: false },
    ]);
    expect(fc.features).toHaveLength(1);
    expect(fc.features[0]!.properties).toMatchObject({ goal: "G1", outcome: "succeed" });
  });

  it("chooses a graticule step that draws a few lines and labels them by hemisphere", () => {
    expect(graticuleStep([-122.1, 36.6, -121.7, 36.85])).toBe(0.1);
    expect(graticuleStep([-180, -80, 180, 80])).toBe(30);
    const { labels } = graticule([-122.15, 36.65, -121.7, 36.85]);
    expect(labels.filter((l) => l.kind === "parallel").map((l) => l.label)).toEqual(["36.7°N", "36.8°N"]);
    expect(labels.find((l) => l.kind === "meridian")?.label).toBe("122.1°W");
  });

  it("finds areas by id or by the words of their title", () => {
    const list = [area("A", [], { title: "Area A" }), area("LANE", [], { title: "Monterey Bay traffic lane" })];
    expect(findAreas(list, "monterey lane").map((a) => a.id)).toEqual(["LANE"]);
    expect(findAreas(list, "a").map((a) => a.id)).toEqual(["A", "LANE"]);
    expect(findAreas(list, "  ")).toEqual([]);
    expect(boundsOf([[36.7, -121.9], [36.8, -121.8]])).toEqual([-121.9, 36.7, -121.8, 36.8]);
  });
});
