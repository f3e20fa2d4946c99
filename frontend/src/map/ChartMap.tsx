/**
 * The chart: MapLibre GL over an offline coastline (Natural Earth 1:50m land
 * from the world-atlas package, bundled and served by the app), the server's land-mask coastline,
 * a graticule, a metric scale, optional tiles the admin configured, the mission's areas and the
 * registry's charts styled by kind, legs in their outcome's colour, and labels.
 *
 * Labels are DOM markers whose text is set with textContent (MapLibre's symbol layers would need
 * glyphs from a server): user strings stay text, and tests and screen readers can read them.
 */
import "maplibre-gl/dist/maplibre-gl.css";
import "./map.css";

import {
  type GeoJSONSource,
  type LngLatBoundsLike,
  Map as MapLibre,
  Marker,
  NavigationControl,
  ScaleControl,
  type StyleSpecification,
} from "maplibre-gl";
import { useEffect, useMemo, useRef, useState } from "react";

import {
  type AreaStyle,
  areaCollection,
  boundsOf,
  type Bounds,
  CROSSING_COLOUR,
  findAreas,
  graticule,
  labelPoint,
  type LatLon,
  legCollection,
  lineCollection,
  lonLat,
  OUTCOME,
  STYLE_COLOUR,
  STYLE_NAME,
} from "./features";
import { loadLand, findPlace } from "./land";
import { installMapPolicy } from "./trusted";
import type { ChartMapProps } from "./types";

const EMPTY = { type: "FeatureCollection" as const, features: [] };
const WATER = "#dcecf5";

function styleColour(): unknown[] {
  return ["match", ["get", "style"], ...Object.entries(STYLE_COLOUR).flat(), STYLE_COLOUR.area];
}

function baseStyle(tiles: ChartMapProps["tiles"]): StyleSpecification {
  const geo = (id: string) => [id, { type: "geojson", data: EMPTY }] as const;
  return {
    version: 8,
    sources: {
      ...Object.fromEntries(["land", "coastline", "graticule", "areas", "legs", "route"].map(geo)),
      ...(tiles ? { tiles: { type: "raster", tiles: [tiles.template], tileSize: 256, maxzoom: 19 } } : {}),
    },
    layers: [
      { id: "water", type: "background", paint: { "background-color": WATER } },
      ...(tiles ? [{ id: "tiles", type: "raster" as const, source: "tiles", paint: { "raster-opacity": 0.85 } }] : []),
      { id: "land", type: "fill", source: "land", paint: { "fill-color": "#f1ebdc", "fill-opacity": tiles ? 0.35 : 1 } },
      { id: "land-edge", type: "line", source: "land", paint: { "line-color": "#a1887f", "line-width": 0.8 } },
      { id: "coastline", type: "line", source: "coastline", paint: { "line-color": "#795548", "line-width": 1.2 } },
      { id: "graticule", type: "line", source: "graticule", paint: { "line-color": "#4a6478", "line-opacity": 0.35, "line-width": 0.7 } },
      {
        id: "areas-fill",
        type: "fill",
        source: "areas",
        filter: ["==", ["geometry-type"], "Polygon"],
        paint: {
          "fill-color": styleColour() as never,
          "fill-opacity": ["case", ["==", ["get", "style"], "land"], 0.45, ["get", "chosen"], 0.4, 0.2] as never,
        },
      },
      {
        id: "areas-line",
        type: "line",
        source: "areas",
        filter: ["!=", ["get", "style"], "keep_out"],
        paint: {
          "line-color": ["case", ["get", "crossed"], CROSSING_COLOUR, styleColour()] as never,
          "line-width": ["case", ["get", "crossed"], 3, ["get", "selected"], 3, 1.5] as never,
        },
      },
      // Keep-out is the one area no part of the mission may enter: a heavy dashed red border.
      {
        id: "areas-keep-out",
        type: "line",
        source: "areas",
        filter: ["==", ["get", "style"], "keep_out"],
        paint: { "line-color": STYLE_COLOUR.keep_out, "line-width": 3, "line-dasharray": [2, 1] },
      },
      {
        id: "legs-crossed",
        type: "line",
        source: "legs",
        filter: ["get", "crossed"],
        paint: { "line-color": CROSSING_COLOUR, "line-width": 5, "line-opacity": 0.8 },
      },
      {
        id: "legs-succeed",
        type: "line",
        source: "legs",
        filter: ["==", ["get", "outcome"], "succeed"],
        paint: { "line-color": OUTCOME.succeed.colour, "line-width": 1.8 },
      },
      {
        id: "legs-other",
        type: "line",
        source: "legs",
        filter: ["!=", ["get", "outcome"], "succeed"],
        paint: {
          "line-color": ["match", ["get", "outcome"], "fail", OUTCOME.fail.colour, OUTCOME.violate.colour] as never,
          "line-width": 1.8,
          "line-dasharray": [3, 2],
        },
      },
      {
        id: "route",
        type: "line",
        source: "route",
        paint: { "line-color": "#1a7f37", "line-width": 2.5, "line-dasharray": [2, 1] },
      },
    ],
  } as StyleSpecification;
}

interface Label {
  key: string;
  at: [number, number];
  text: string;
  sub?: string;
  /** Several items in one label (legs along one segment), each with its own data. */
  parts?: { text: string; className: string; data: Record<string, string>; title: string }[];
  className: string;
  data: Record<string, string>;
  anchor?: "center" | "top" | "left" | "bottom-left";
}

function labelElement(label: Label): HTMLElement {
  const el = document.createElement("div");
  el.className = `map-label ${label.className}`;
  el.title = label.sub ? `${label.text} (${label.sub})` : label.text;
  if (label.parts) {
    el.title = label.parts.map((p) => p.title).join("; ");
    const row = document.createElement("span");
    row.className = "map-label-parts";
    for (const part of label.parts) {
      const span = document.createElement("span");
      span.className = part.className;
      span.textContent = part.text; // text, never markup
      for (const [k, v] of Object.entries(part.data)) span.dataset[k] = v;
      row.append(span);
    }
    el.append(row);
  } else {
    const main = document.createElement("span");
    main.textContent = label.text; // text, never markup
    el.append(main);
  }
  if (label.sub) {
    const sub = document.createElement("span");
    sub.className = "map-label-sub";
    sub.textContent = label.sub;
    el.append(sub);
  }
  for (const [k, v] of Object.entries(label.data)) el.dataset[k] = v;
  return el;
}

/** Hide later labels that overlap earlier ones (areas first, then crossed legs, then legs). */
function declutter(markers: { marker: Marker; priority: number }[]) {
  const placed: DOMRect[] = [];
  const sorted = [...markers].sort((a, b) => a.priority - b.priority);
  for (const { marker } of sorted) {
    const el = marker.getElement();
    el.classList.remove("map-label-hidden");
    const box = el.getBoundingClientRect();
    const hit = placed.some((p) => box.left < p.right && box.right > p.left && box.top < p.bottom && box.bottom > p.top);
    if (hit) el.classList.add("map-label-hidden");
    else placed.push(box);
  }
}

const PRESENT_ORDER: AreaStyle[] = ["keep_out", "land", "protected", "lane", "anchorage", "area"];

export default function ChartMap(props: ChartMapProps) {
  const { label, testId, areas, legs = [], route = [], coastline = [], tiles = null, selected = null } = props;
  const container = useRef<HTMLDivElement>(null);
  const map = useRef<MapLibre | null>(null);
  const [ready, setReady] = useState(false);
  const [landLoaded, setLandLoaded] = useState(false);
  const [view, setView] = useState<Bounds | null>(null);
  const latest = useRef(props);
  latest.current = props;

  // One map per mounted chart; tiles are fixed for its life (the server's setting).
  useEffect(() => {
    installMapPolicy();
    const m = new MapLibre({
      container: container.current!,
      style: baseStyle(tiles),
      center: [0, 20],
      zoom: 1,
      attributionControl: false,
      dragRotate: false,
      pitchWithRotate: false,
      touchPitch: false,
      maxZoom: 18,
      renderWorldCopies: false,
      fadeDuration: 0,
    });
    m.touchZoomRotate.disableRotation();
    m.keyboard.disableRotation();
    m.addControl(new NavigationControl({ showCompass: false }), "top-right");
    m.addControl(new ScaleControl({ unit: "metric", maxWidth: 120 }), "bottom-left");
    const viewNow = () => {
      const b = m.getBounds();
      setView([b.getWest(), b.getSouth(), b.getEast(), b.getNorth()]);
    };
    m.on("load", () => {
      setReady(true);
      viewNow();
    });
    m.on("moveend", viewNow);
    m.on("click", (e) => {
      const add = latest.current.onAddVertex;
      if (add) {
        add([round6(e.lngLat.lat), round6(e.lngLat.lng)]);
        return;
      }
      const hit = m.queryRenderedFeatures(e.point, { layers: ["areas-fill"] }).find((f) => f.properties?.source === "area");
      if (hit && latest.current.onSelect) latest.current.onSelect(String(hit.properties.id));
    });
    map.current = m;
    let live = true;
    loadLand()
      .then((land) => {
        if (!live) return;
        const put = () => {
          (m.getSource("land") as GeoJSONSource | undefined)?.setData(land as never);
          setLandLoaded(true);
        };
        if (m.isStyleLoaded()) put();
        else m.once("load", put);
      })
      .catch(() => setLandLoaded(false));
    return () => {
      live = false;
      m.remove();
      map.current = null;
    };
    // eslint-disable-next-line react-hooks/exhaustive-deps -- the map lives as long as the component
  }, []);

  // Keyed by content: a save that hands back equal orders redraws nothing.
  const areaKey = JSON.stringify(areas);
  const legKey = JSON.stringify(legs);
  const routeKey = JSON.stringify(route);
  // eslint-disable-next-line react-hooks/exhaustive-deps -- areaKey stands for areas
  const areaData = useMemo(() => areaCollection(areas), [areaKey]);
  // eslint-disable-next-line react-hooks/exhaustive-deps -- legKey stands for legs
  const legData = useMemo(() => legCollection(legs), [legKey]);
  const coastData = useMemo(() => lineCollection(coastline), [coastline]);
  // eslint-disable-next-line react-hooks/exhaustive-deps -- routeKey stands for route
  const routeData = useMemo(() => lineCollection([route.map((r) => r.at)]), [routeKey]);
  const grid = useMemo(() => (view ? graticule(view) : null), [view]);

  // Each source is replaced only when its own data changed: a software-rendered map redraws
  // (and re-tiles in its worker) on every setData.
  useSourceData(map, ready, "areas", areaData);
  useSourceData(map, ready, "legs", legData);
  useSourceData(map, ready, "coastline", coastData);
  useSourceData(map, ready, "route", routeData);
  useSourceData(map, ready, "graticule", grid?.lines ?? EMPTY);

  // A vertex typed (or pasted) outside the view would be drawn where nobody sees it: then the
  // view moves to show every area again.
  useEffect(() => {
    const m = map.current;
    const area = areas.find((a) => a.id === selected && a.source === "area");
    if (!m || !ready || !area) return;
    const view = m.getBounds();
    const outside = area.polygon.some((p) => {
      const at = lonLat(p);
      return at !== null && !view.contains(at);
    });
    const b = boundsOf(areas.flatMap((a) => a.polygon));
    if (outside && b) fit(m, b, 48);
  }, [ready, areas, selected]);

  // Fit to everything drawn when the set of things changes (fitKey), not at every vertex edit.
  const allPoints = useMemo(
    () => [...areas.flatMap((a) => a.polygon), ...legs.flatMap((l) => [l.start, l.end]), ...route.map((r) => r.at)],
    // eslint-disable-next-line react-hooks/exhaustive-deps -- refit on fitKey only
    [props.fitKey, ready],
  );
  useEffect(() => {
    const m = map.current;
    if (!m || !ready) return;
    const b = boundsOf(allPoints);
    if (!b) return;
    fit(m, b, 48);
  }, [allPoints, ready]);

  // Labels: areas and charts (id, title, tags), legs (goal and outcome letter), route steps,
  // graticule values at the map's edges.
  const contentKey = `${areaKey}|${legKey}|${routeKey}`;
  const labels = useMemo(() => {
    const out: (Label & { priority: number })[] = [];
    for (const a of areas) {
      const at = labelPoint(a.polygon);
      if (!at) continue;
      out.push({
        key: `${a.source}-${a.id}`,
        at,
        text: a.title ? `${a.id} ${a.title}` : a.id,
        sub: a.tags && a.tags.length > 0 ? a.tags.join(", ") : a.source === "chart" ? STYLE_NAME[a.style] : undefined,
        className: `map-label-area map-style-${a.style}${a.crossed ? " crossed" : ""}${a.chosen ? " chosen" : ""}${a.id === selected ? " selected" : ""}`,
        data: {
          testid: `${a.source === "chart" ? "chart" : "plan-area"}-${a.id}`,
          style: a.style,
          vertices: String(a.polygon.length),
          ...(a.crossed ? { crossed: "true" } : {}),
        },
        priority: a.source === "area" ? 0 : 1,
      });
    }
    if (props.legLabels !== false) {
      // Legs along the same segment (s, f and c of one goal often go the same way) share one
      // label listing each: "G2 f c" instead of three labels on top of each other.
      const groups = new Map<string, { at: [number, number]; legs: typeof legs[number][] }>();
      for (const l of legs) {
        const a = lonLat(l.start);
        const b = lonLat(l.end);
        if (!a || !b) continue;
        const key = [...a, ...b].map((v) => v.toFixed(5)).join(",");
        // A third of the way from the goal that ends: legs in opposite directions stay apart.
        const at: [number, number] = [a[0] + (b[0] - a[0]) / 3, a[1] + (b[1] - a[1]) / 3];
        const group = groups.get(key) ?? { at, legs: [] };
        group.legs.push(l);
        groups.set(key, group);
      }
      for (const [key, g] of groups) {
        const crossed = g.legs.some((l) => l.crossed);
        out.push({
          key: `legs-${key}`,
          at: g.at,
          text: "",
          parts: g.legs.map((l) => ({
            text: `${l.goal} ${OUTCOME[l.outcome as keyof typeof OUTCOME]?.letter ?? "?"}`,
            className: `leg-${l.outcome}${l.crossed ? " leg-crossing" : ""}`,
            data: { leg: `${l.goal} ${l.outcome}`, to: l.to },
            title: `${l.goal} ${l.outcome} → ${l.to}${l.lengthM !== undefined ? `: ${Math.round(l.lengthM)} m` : ""}`,
          })),
          className: `map-label-leg${crossed ? " leg-crossing" : ""}`,
          data: {},
          priority: crossed ? 2 : 3,
        });
      }
    }
    route.forEach((r, i) => {
      const at = lonLat(r.at);
      if (at) out.push({ key: `route-${i}`, at, text: r.label, className: "map-label-route", data: {}, anchor: "bottom-left", priority: 1 });
    });
    return out;
    // eslint-disable-next-line react-hooks/exhaustive-deps -- contentKey stands for areas, legs, route
  }, [contentKey, selected, props.legLabels]);

  // Graticule values at the map's top and left edges, rebuilt when the view moves.
  const gridLabels = useMemo(() => {
    const out: (Label & { priority: number })[] = [];
    if (grid && view) {
      const [west, , , north] = view;
      for (const g of grid.labels) {
        out.push({
          key: `grid-${g.kind}-${g.value}`,
          at: g.kind === "meridian" ? [g.value, north] : [west, g.value],
          text: g.label,
          className: "map-label-grid",
          data: { grid: g.kind },
          anchor: g.kind === "meridian" ? "top" : "left",
          priority: 9,
        });
      }
    }
    return out;
  }, [grid, view]);

  useEffect(() => {
    const m = map.current;
    if (!m || !ready) return;
    const markers = labels.map((l) => ({
      marker: new Marker({ element: labelElement(l), anchor: l.anchor ?? "center" }).setLngLat(l.at).addTo(m),
      priority: l.priority,
    }));
    declutter(markers);
    const again = () => declutter(markers);
    m.on("zoomend", again);
    return () => {
      m.off("zoomend", again);
      markers.forEach(({ marker }) => marker.remove());
    };
  }, [ready, labels]);
  useEffect(() => {
    const m = map.current;
    if (!m || !ready) return;
    const markers = gridLabels.map((l) => new Marker({ element: labelElement(l), anchor: l.anchor ?? "center" }).setLngLat(l.at).addTo(m));
    return () => markers.forEach((marker) => marker.remove());
  }, [ready, gridLabels]);

  // The selected area's vertices: numbered handles, draggable when the chart is editable.
  const editing = props.onMoveVertex;
  const selectedArea = areas.find((a) => a.id === selected && a.source === "area");
  // Handles are rebuilt when the polygon changes, not when a save hands back equal orders.
  const handleKey = selectedArea ? JSON.stringify([selectedArea.id, selectedArea.polygon]) : "";
  useEffect(() => {
    const m = map.current;
    if (!m || !ready || !selectedArea || !editing) return;
    const handles = selectedArea.polygon.flatMap((p, i) => {
      const at = lonLat(p);
      if (!at) return [];
      const el = document.createElement("div");
      el.className = "map-vertex";
      el.textContent = String(i + 1);
      el.dataset.testid = `vertex-${selectedArea.id}-${i + 1}`;
      el.title = `Vertex ${i + 1} of ${selectedArea.id}: drag to move`;
      const marker = new Marker({ element: el, draggable: true }).setLngLat(at).addTo(m);
      marker.on("dragend", () => {
        const ll = marker.getLngLat();
        latest.current.onMoveVertex?.(selectedArea.id, i, [round6(ll.lat), round6(ll.lng)]);
      });
      return [marker];
    });
    return () => handles.forEach((h) => h.remove());
    // eslint-disable-next-line react-hooks/exhaustive-deps -- handleKey stands for selectedArea
  }, [ready, handleKey, editing]);

  const adding = Boolean(props.onAddVertex);
  useEffect(() => {
    const canvas = map.current?.getCanvas();
    if (canvas) canvas.style.cursor = adding ? "crosshair" : "";
  }, [adding, ready]);

  const present = PRESENT_ORDER.filter((s) => areas.some((a) => a.style === s));
  return (
    <div className="chart-map-wrap">
      <MapSearch
        areas={areas}
        onFound={(b, id) => {
          if (map.current) fit(map.current, b, 60);
          if (id && latest.current.onSelect) latest.current.onSelect(id);
        }}
      />
      <div
        ref={container}
        className={`chart-map${adding ? " adding" : ""}`}
        role="region"
        aria-label={label}
        data-testid={testId}
        data-ready={ready ? "true" : "false"}
        data-land={landLoaded ? "natural-earth-50m" : "loading"}
        data-coastline-segments={String(coastData.features.length)}
        data-tiles={tiles ? "on" : "off"}
      />
      <ul className="chart-legend" aria-label="Legend">
        {present.map((s) => (
          <li key={s}>
            <span className={`swatch swatch-area map-style-${s}`} style={{ borderColor: STYLE_COLOUR[s], background: `${STYLE_COLOUR[s]}40` }} />
            {STYLE_NAME[s]}
          </li>
        ))}
        {legs.length > 0 &&
          (Object.keys(OUTCOME) as (keyof typeof OUTCOME)[]).map((o) => (
            <li key={o}>
              <span className={`swatch swatch-leg${o === "succeed" ? "" : " dashed"}`} style={{ borderColor: OUTCOME[o].colour }} />
              <span style={{ color: OUTCOME[o].colour }}>
                {OUTCOME[o].letter} leg on {OUTCOME[o].name}
              </span>
            </li>
          ))}
        {legs.some((l) => l.crossed) && (
          <li>
            <span className="swatch swatch-leg" style={{ borderColor: CROSSING_COLOUR, borderTopWidth: 5 }} />
            crosses a forbidden area
          </li>
        )}
        {route.length > 0 && (
          <li>
            <span className="swatch swatch-leg dashed" style={{ borderColor: "#1a7f37" }} />
            planned route
          </li>
        )}
        <li>
          <span className="swatch swatch-area" style={{ borderColor: "#a1887f", background: "#f1ebdc" }} />
          land (Natural Earth 1:50m{coastline.length > 0 ? "; brown line: the server's 1 km land mask" : ""})
        </li>
        {grid && <li>graticule every {formatStep(grid.labels)}</li>}
      </ul>
      {tiles && <p className="chart-attribution">Map tiles: {tiles.attribution || hostOf(tiles.template)}</p>}
    </div>
  );
}

function useSourceData(map: { current: MapLibre | null }, ready: boolean, id: string, data: unknown) {
  useEffect(() => {
    if (ready) (map.current?.getSource(id) as GeoJSONSource | undefined)?.setData(data as never);
  }, [map, ready, id, data]);
}

function MapSearch({ areas, onFound }: { areas: ChartMapProps["areas"]; onFound: (b: Bounds, id?: string) => void }) {
  const [query, setQuery] = useState("");
  const [message, setMessage] = useState("");
  const listId = useRef(`map-search-${Math.random().toString(36).slice(2)}`).current;
  return (
    <form
      className="map-search"
      role="search"
      onSubmit={async (e) => {
        e.preventDefault();
        const hit = findAreas(areas, query)[0];
        const b = hit ? boundsOf(hit.polygon) : null;
        if (hit && b) {
          onFound(b, hit.source === "area" ? hit.id : undefined);
          setMessage(`${hit.source === "area" ? "Area" : "Chart"} ${hit.id}`);
          return;
        }
        const place = query.trim() ? await findPlace(query) : null;
        if (place) {
          onFound(place.bounds);
          setMessage(place.name);
        } else setMessage(query.trim() ? `Nothing named “${query.trim()}”` : "");
      }}
    >
      <label htmlFor={`${listId}-input`}>Find an area, chart or country</label>
      <input id={`${listId}-input`} list={listId} value={query} onChange={(e) => setQuery(e.target.value)} />
      <datalist id={listId}>
        {areas.map((a) => (
          <option key={`${a.source}-${a.id}`} value={a.id}>
            {a.title ?? ""}
          </option>
        ))}
      </datalist>
      <button type="submit">Find</button>
      <output aria-live="polite">{message}</output>
    </form>
  );
}

function fit(m: MapLibre, b: Bounds, padding: number) {
  // A single point or a line still gets an extent (about 500 m).
  const pad = 0.0025;
  const box: LngLatBoundsLike =
    b[2] - b[0] < 1e-6 && b[3] - b[1] < 1e-6 ? [b[0] - pad, b[1] - pad, b[2] + pad, b[3] + pad] : b;
  const canvas = m.getCanvas();
  const p = Math.max(0, Math.min(padding, canvas.clientWidth / 4, canvas.clientHeight / 4));
  m.fitBounds(box, { padding: p, animate: false, maxZoom: 16 });
}

function formatStep(labels: { kind: string; value: number }[]): string {
  const lats = labels.filter((l) => l.kind === "parallel").map((l) => l.value);
  const lons = labels.filter((l) => l.kind === "meridian").map((l) => l.value);
  const values = lats.length > 1 ? lats : lons;
  if (values.length < 2) return "degree step";
  const step = Math.abs(values[1]! - values[0]!);
  return `${Number(step.toPrecision(3))}°`;
}

function hostOf(template: string): string {
  try {
    return new URL(template.replace(/[{}]/g, "")).host;
  } catch {
    return "configured server";
  }
}

function round6(n: number): number {
  return Math.round(n * 1e6) / 1e6;
}

export type { LatLon };
