/**
 * Offline geography from Natural Earth (public domain) via the world-atlas package: the files
 * are bundled as assets and served by the app itself, so the chart needs no network. Land is
 * the 1:50m set (about 540 kB, fetched once per page); country names for the search are 1:110m.
 */
import countriesUrl from "world-atlas/countries-110m.json?url";
import landUrl from "world-atlas/land-50m.json?url";
import { feature } from "topojson-client";
import type { GeometryCollection, Topology } from "topojson-specification";

import type { Bounds } from "./features";

let land: Promise<unknown> | null = null;

export function loadLand(): Promise<unknown> {
  land ??= fetch(landUrl)
    .then((r) => {
      if (!r.ok) throw new Error(`the coastline could not be loaded (${r.status})`);
      return r.json() as Promise<Topology>;
    })
    .then((topo) => feature(topo, topo.objects.land as GeometryCollection));
  return land;
}

interface Country {
  name: string;
  bounds: Bounds;
}
let countries: Promise<Country[]> | null = null;

function loadCountries(): Promise<Country[]> {
  countries ??= fetch(countriesUrl)
    .then((r) => r.json() as Promise<Topology>)
    .then((topo) => {
      const fc = feature(topo, topo.objects.countries as GeometryCollection<{ name: string }>);
      return fc.features.map((f) => ({ name: String(f.properties?.name ?? ""), bounds: bboxOf(f.geometry) }));
    });
  return countries;
}

/** The first country whose name contains the query (any case), or null. */
export async function findPlace(query: string): Promise<Country | null> {
  const q = query.trim().toLowerCase();
  if (!q) return null;
  try {
    const all = await loadCountries();
    return all.find((c) => c.name.toLowerCase() === q) ?? all.find((c) => c.name.toLowerCase().includes(q)) ?? null;
  } catch {
    return null;
  }
}

function bboxOf(geometry: unknown): Bounds {
  const b: Bounds = [180, 90, -180, -90];
  const visit = (c: unknown): void => {
    if (Array.isArray(c) && typeof c[0] === "number" && typeof c[1] === "number") {
      b[0] = Math.min(b[0], c[0]);
      b[1] = Math.min(b[1], c[1]);
      b[2] = Math.max(b[2], c[0]);
      b[3] = Math.max(b[3], c[1]);
    } else if (Array.isArray(c)) c.forEach(visit);
  };
  visit((geometry as { coordinates?: unknown } | null)?.coordinates);
  return b;
}
