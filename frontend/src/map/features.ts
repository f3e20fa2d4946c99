/**
 * Pure geometry of the chart (no MapLibre here, so it is unit-tested under Node and stays out of
 * the main bundle): areas and charts as GeoJSON in (longitude, latitude) order, legs, a
 * graticule at a readable step, and how an area is styled from its tags or chart kind.
 */
import { numberPair } from "../api/pair";

/** (latitude, longitude) in degrees, as the orders and the API write them. */
export type LatLon = [number, number];
export type Bounds = [west: number, south: number, east: number, north: number];

/** How an area is drawn: the chart checks' fixed tags (DESIGN.md, GEO) get their own style. */
export type AreaStyle = "keep_out" | "land" | "protected" | "lane" | "anchorage" | "area";

const STYLE_OF_TAG: Record<string, AreaStyle> = {
  keep_out: "keep_out",
  land: "land",
  marine_protected_area: "protected",
  protected_area: "protected",
  shipping_lane: "lane",
  traffic_separation: "lane",
  anchorage: "anchorage",
};
// The strongest restriction wins when an area carries several tags.
const PRECEDENCE: AreaStyle[] = ["keep_out", "land", "protected", "lane", "anchorage", "area"];

export function areaStyle(tags: readonly (string | null | undefined)[]): AreaStyle {
  const styles = new Set(tags.map((t) => (t ? STYLE_OF_TAG[t] : undefined)).filter(Boolean));
  return PRECEDENCE.find((s) => styles.has(s)) ?? "area";
}

/** What the legend and the layers agree on; text colours pass WCAG AA on white. */
export const STYLE_COLOUR: Record<AreaStyle, string> = {
  keep_out: "#b71c1c",
  land: "#6d4c41",
  protected: "#1b5e20",
  lane: "#8d6e00",
  anchorage: "#0d47a1",
  area: "#0b5cad",
};
export const STYLE_NAME: Record<AreaStyle, string> = {
  keep_out: "Keep-out",
  land: "Land",
  protected: "Protected area",
  lane: "Shipping lane / traffic separation",
  anchorage: "Anchorage",
  area: "Mission area",
};
export const OUTCOME = {
  succeed: { letter: "s", colour: "#1b5e20", name: "succeed" },
  fail: { letter: "f", colour: "#a23c00", name: "fail" },
  violate: { letter: "c", colour: "#6a1b9a", name: "constraint" },
} as const;
export const CROSSING_COLOUR = "#d50000";

export interface MapArea {
  id: string;
  title?: string | null;
  /** "area" (the mission's) or "chart" (the shared registry's). */
  source: "area" | "chart";
  style: AreaStyle;
  polygon: readonly (readonly number[])[];
  crossed?: boolean;
  chosen?: boolean;
  selected?: boolean;
  /** Tags shown under the label. */
  tags?: readonly string[];
}

export interface MapLeg {
  goal: string;
  outcome: string;
  to: string;
  start: readonly number[];
  end: readonly number[];
  crossed: boolean;
  lengthM?: number;
}

type Position = [number, number];
interface Feature<G> {
  type: "Feature";
  id?: number;
  properties: Record<string, string | number | boolean>;
  geometry: G;
}
export interface Collection<G = unknown> {
  type: "FeatureCollection";
  features: Feature<G>[];
}

/** [lon, lat] of a (lat, lon) pair; null when a coordinate is missing or not finite. */
export function lonLat(point: readonly number[]): Position | null {
  const [lat, lon] = numberPair(point);
  return Number.isFinite(lat) && Number.isFinite(lon) ? [lon, lat] : null;
}

function ring(polygon: MapArea["polygon"]): Position[] {
  const pts = polygon.map(lonLat).filter((p): p is Position => p !== null);
  if (pts.length >= 3) {
    const [first, last] = [pts[0]!, pts[pts.length - 1]!];
    if (first[0] !== last[0] || first[1] !== last[1]) pts.push(first);
  }
  return pts;
}

/** Polygons of 3+ vertices are filled; 2 vertices draw as a line so a new area shows at once. */
export function areaCollection(list: readonly MapArea[]): Collection {
  const features = list.flatMap((a): Feature<unknown>[] => {
    const pts = ring(a.polygon);
    const properties = {
      id: a.id,
      source: a.source,
      style: a.style,
      crossed: Boolean(a.crossed),
      chosen: Boolean(a.chosen),
      selected: Boolean(a.selected),
    };
    if (pts.length >= 4) return [{ type: "Feature", properties, geometry: { type: "Polygon", coordinates: [pts] } }];
    if (pts.length >= 2) return [{ type: "Feature", properties, geometry: { type: "LineString", coordinates: pts } }];
    return [];
  });
  return { type: "FeatureCollection", features };
}

export function legCollection(legs: readonly MapLeg[]): Collection {
  const features = legs.flatMap((l): Feature<unknown>[] => {
    const a = lonLat(l.start);
    const b = lonLat(l.end);
    if (!a || !b) return [];
    return [
      {
        type: "Feature",
        properties: { goal: l.goal, outcome: l.outcome, crossed: l.crossed },
        geometry: { type: "LineString", coordinates: [a, b] },
      },
    ];
  });
  return { type: "FeatureCollection", features };
}

export function lineCollection(lines: readonly (readonly (readonly number[])[])[]): Collection {
  const features = lines.flatMap((line): Feature<unknown>[] => {
    const pts = line.map(lonLat).filter((p): p is Position => p !== null);
    return pts.length >= 2 ? [{ type: "Feature", properties: {}, geometry: { type: "LineString", coordinates: pts } }] : [];
  });
  return { type: "FeatureCollection", features };
}

/** The box around every point, or null when there is none. */
export function boundsOf(points: readonly (readonly number[])[]): Bounds | null {
  const pts = points.map(lonLat).filter((p): p is Position => p !== null);
  if (pts.length === 0) return null;
  const xs = pts.map((p) => p[0]);
  const ys = pts.map((p) => p[1]);
  return [Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)];
}

/** The centroid of a polygon's vertices (where its label goes). */
export function labelPoint(polygon: MapArea["polygon"]): Position | null {
  const pts = polygon.map(lonLat).filter((p): p is Position => p !== null);
  if (pts.length === 0) return null;
  return [pts.reduce((s, p) => s + p[0], 0) / pts.length, pts.reduce((s, p) => s + p[1], 0) / pts.length];
}

const STEPS = [30, 10, 5, 2, 1, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001];

/** The graticule step (degrees) that draws about 3-8 lines across the larger side of the box. */
export function graticuleStep(bounds: Bounds): number {
  const span = Math.max(bounds[2] - bounds[0], bounds[3] - bounds[1], 1e-9);
  return STEPS.find((s) => span / s >= 3) ?? STEPS[STEPS.length - 1]!;
}

export interface GraticuleLine {
  kind: "meridian" | "parallel";
  value: number;
  label: string;
}

/** Meridians and parallels over the box at its step, with their labels (e.g. 36.70°N). */
export function graticule(bounds: Bounds): { lines: Collection; labels: GraticuleLine[] } {
  const step = graticuleStep(bounds);
  const decimals = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
  const [west, south, east, north] = bounds;
  const values = (lo: number, hi: number) => {
    const out: number[] = [];
    for (let k = Math.ceil(lo / step); k * step <= hi && out.length < 60; k++) out.push(Number((k * step).toFixed(decimals + 1)));
    return out;
  };
  const lats = values(Math.max(-85, south), Math.min(85, north));
  const lons = values(west, east);
  const label = (v: number, pos: string, neg: string) => `${Math.abs(v).toFixed(decimals)}°${v >= 0 ? pos : neg}`;
  const features: Feature<unknown>[] = [
    ...lons.map((lon): Feature<unknown> => ({
      type: "Feature",
      properties: { kind: "meridian" },
      geometry: { type: "LineString", coordinates: [[lon, Math.max(-85, south)], [lon, Math.min(85, north)]] },
    })),
    ...lats.map((lat): Feature<unknown> => ({
      type: "Feature",
      properties: { kind: "parallel" },
      geometry: { type: "LineString", coordinates: [[west, lat], [east, lat]] },
    })),
  ];
  return {
    lines: { type: "FeatureCollection", features },
    labels: [
      ...lons.map((v): GraticuleLine => ({ kind: "meridian", value: v, label: label(v, "E", "W") })),
      ...lats.map((v): GraticuleLine => ({ kind: "parallel", value: v, label: label(v, "N", "S") })),
    ],
  };
}

/** Areas whose id or title contains every word of the query (any case). */
export function findAreas(list: readonly MapArea[], query: string): MapArea[] {
  const words = query.toLowerCase().split(/\s+/).filter(Boolean);
  if (words.length === 0) return [];
  return list.filter((a) => {
    const text = `${a.id} ${a.title ?? ""}`.toLowerCase();
    return words.every((w) => text.includes(w));
  });
}
