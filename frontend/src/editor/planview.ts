/**
 * Geometry of the plan view: latitude/longitude to SVG coordinates (equirectangular, scaled by
 * cos(latitude) so shapes keep their proportions; no map tiles) and back, plus the local metre
 * frame of the planning problem (centred on the start, as the server builds it).
 */
import { numberPair } from "../api/pair";
import type { Coordinates, LatLon } from "./model";

export const EARTH_RADIUS_M = 6_371_000;

export interface View {
  width: number;
  height: number;
  /** Bounds in projected units (x = lon * cos(lat0), y = lat). */
  minX: number;
  maxX: number;
  minY: number;
  maxY: number;
  cos: number;
  scale: number;
  pad: number;
}

/** A view that fits every point in a width x height box (with padding). */
export function fitView(points: readonly Coordinates[], width: number, height: number, pad = 24): View {
  const pts: LatLon[] = points.length > 0 ? points.map(numberPair) : [[0, 0]];
  const lat0 = pts.reduce((s, p) => s + p[0], 0) / pts.length;
  const cos = Math.cos((lat0 * Math.PI) / 180) || 1;
  const xs = pts.map((p) => p[1] * cos);
  const ys = pts.map((p) => p[0]);
  let minX = Math.min(...xs);
  let maxX = Math.max(...xs);
  let minY = Math.min(...ys);
  let maxY = Math.max(...ys);
  // A single point or a line still gets a visible extent.
  const span = Math.max(maxX - minX, maxY - minY, 1e-4);
  if (maxX - minX < span / 10) {
    minX -= span / 2;
    maxX += span / 2;
  }
  if (maxY - minY < span / 10) {
    minY -= span / 2;
    maxY += span / 2;
  }
  const scale = Math.min((width - 2 * pad) / (maxX - minX), (height - 2 * pad) / (maxY - minY));
  return { width, height, minX, maxX, minY, maxY, cos, scale, pad };
}

/** Latitude/longitude -> SVG x, y (north up). */
export function project(view: View, point: Coordinates): [number, number] {
  const [lat, lon] = numberPair(point);
  const x = view.pad + (lon * view.cos - view.minX) * view.scale;
  const y = view.height - view.pad - (lat - view.minY) * view.scale;
  return [x, y];
}

/** SVG x, y -> latitude/longitude, rounded to 6 decimals (about 0.1 m). */
export function unproject(view: View, x: number, y: number): LatLon {
  const lon = ((x - view.pad) / view.scale + view.minX) / view.cos;
  const lat = (view.height - view.pad - y) / view.scale + view.minY;
  return [round6(lat), round6(lon)];
}

export function round6(n: number): number {
  return Math.round(n * 1e6) / 1e6;
}

/** Local metres (centred on `origin`, as countersign.plan/1 problems built from orders) -> lat/lon.
 * `point` is (east, north), as an answer reads it (numberPair: a missing coordinate gives NaN,
 * which draws nothing, rather than a point at the origin). */
export function fromMetres(origin: LatLon, point: readonly number[]): LatLon {
  const [lat0, lon0] = origin;
  const [east, north] = numberPair(point);
  const cos = Math.cos((lat0 * Math.PI) / 180);
  const lat = lat0 + ((north / EARTH_RADIUS_M) * 180) / Math.PI;
  const lon = lon0 + ((east / (EARTH_RADIUS_M * cos)) * 180) / Math.PI;
  return [lat, lon];
}

/** Centroid of a polygon's vertices (for labels). */
export function centroid(points: readonly Coordinates[]): LatLon {
  if (points.length === 0) return [0, 0];
  const pts = points.map(numberPair);
  return [pts.reduce((s, p) => s + p[0], 0) / pts.length, pts.reduce((s, p) => s + p[1], 0) / pts.length];
}
