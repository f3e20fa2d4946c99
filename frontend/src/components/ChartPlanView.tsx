/**
 * Plan view of a mission's geography (issue 21): areas, registry charts, each outcome edge's
 * leg (letter and colour of its outcome), the GEO crossings highlighted, and the coastline from
 * the server's bundled land mask. Drawn as SVG from /api/plan-view in Web Mercator; map tiles
 * beneath only when the server configures them (COUNTERSIGN_MAP_TILES, /api/client-config),
 * otherwise none are requested and it works offline. Every name is React text, never markup.
 */
import { useLoad } from "../useLoad";
import { api, type Schema, unwrap } from "../api/client";
import { numberPair, pairOf } from "../api/pair";
import { ErrorMessage, Loading } from "./Status";

/** (latitude, longitude) as an answer reads it (api/pair.ts: a missing coordinate is NaN). */
type LatLon = readonly number[];
/** POST /api/plan-view: what the plan view draws. */
export type PlanData = Schema<"PlanViewOut">;

const OUTCOME_STYLE: Record<"succeed" | "fail" | "violate", { letter: string; colour: string }> = {
  succeed: { letter: "s", colour: "#2e7d32" },
  fail: { letter: "f", colour: "#ef6c00" },
  violate: { letter: "c", colour: "#6a1b9a" },
};
const CHART_COLOUR: Record<string, string> = {
  keep_out: "#c62828",
  land: "#795548",
  protected_area: "#2e7d32",
  shipping_lane: "#f9a825",
  traffic_separation: "#f9a825",
  anchorage: "#1565c0",
  other: "#607d8b",
};
const WIDTH = 720;
const HEIGHT = 480;
const PAD = 16;

const TILE_PX = 256;
const MAX_ZOOM = 19;
const MAX_TILES = 48;

/** Web Mercator in unit coordinates: x east from -180°, y south from 85.05°N, both 0..1. */
function mercator(point: LatLon): [number, number] {
  const [lat, lon] = numberPair(point);
  const sin = Math.sin((Math.max(-85.0511, Math.min(85.0511, lat)) * Math.PI) / 180);
  return [(lon + 180) / 360, 0.5 - Math.log((1 + sin) / (1 - sin)) / (4 * Math.PI)];
}

interface Projection {
  at: (p: LatLon) => [number, number];
  scale: number; // pixels per unit of Mercator
  offset: [number, number]; // pixel position of Mercator (0, 0)
}

function projector(data: PlanData): Projection {
  const projected = [
    ...data.areas.flatMap((a) => a.polygon),
    ...data.legs.flatMap((l) => [l.start, l.end]),
  ].map(mercator);
  const xs = projected.map((p) => p[0]);
  const ys = projected.map((p) => p[1]);
  const [west, east] = xs.length ? [Math.min(...xs), Math.max(...xs)] : [0.49, 0.51];
  const [north, south] = ys.length ? [Math.min(...ys), Math.max(...ys)] : [0.49, 0.51];
  const spanX = Math.max(east - west, 1e-9);
  const spanY = Math.max(south - north, 1e-9);
  const scale = Math.min((WIDTH - 2 * PAD) / spanX, (HEIGHT - 2 * PAD) / spanY);
  const offset: [number, number] = [
    PAD + (WIDTH - 2 * PAD - spanX * scale) / 2 - west * scale,
    PAD + (HEIGHT - 2 * PAD - spanY * scale) / 2 - north * scale,
  ];
  return {
    at: (p) => {
      const [x, y] = mercator(p);
      return [offset[0] + x * scale, offset[1] + y * scale];
    },
    scale,
    offset,
  };
}

export interface Tile {
  url: string;
  x: number;
  y: number;
  size: number;
}

/** The tiles (of a {z}/{x}/{y} template) that cover the drawing, at the zoom nearest its scale. */
export function tilesFor(template: string, projection: Projection): Tile[] {
  let zoom = Math.max(0, Math.min(MAX_ZOOM, Math.round(Math.log2(projection.scale / TILE_PX))));
  for (;;) {
    const n = 2 ** zoom;
    const size = projection.scale / n;
    const range = (offset: number, extent: number): number[] => {
      const first = Math.max(0, Math.floor((-offset / size)));
      const last = Math.min(n - 1, Math.floor((extent - offset) / size));
      return Array.from({ length: Math.max(0, last - first + 1) }, (_, i) => first + i);
    };
    const columns = range(projection.offset[0], WIDTH);
    const rows = range(projection.offset[1], HEIGHT);
    if (columns.length * rows.length > MAX_TILES && zoom > 0) {
      zoom -= 1;
      continue;
    }
    return rows.flatMap((row) =>
      columns.map((column) => ({
        url: template
          .replace("{z}", String(zoom))
          .replace("{x}", String(column))
          .replace("{y}", String(row)),
        x: projection.offset[0] + column * size,
        y: projection.offset[1] + row * size,
        size,
      })),
    );
  }
}

function points(shape: LatLon[], at: (p: LatLon) => [number, number]): string {
  return shape.map((p) => at(p).map((v) => v.toFixed(1)).join(",")).join(" ");
}

export function PlanSvg({ data, tiles = null }: { data: PlanData; tiles?: string | null }) {
  const projection = projector(data);
  const at = projection.at;
  const crossed = new Set(
    data.crossings.filter((c) => c.edge).map((c) => `${c.edge!.goal} ${c.edge!.outcome}`),
  );
  const crossedAreas = new Set(data.crossings.map((c) => c.area).filter(Boolean));
  return (
    <svg
      className="plan-view"
      role="img"
      aria-label="Plan view: areas, charts and legs"
      viewBox={`0 0 ${WIDTH} ${HEIGHT}`}
      width={WIDTH}
      height={HEIGHT}
      style={{ background: "#eef6fb", maxWidth: "100%" }}
    >
      {tiles && (
        <g className="map-tiles" opacity={0.8}>
          {tilesFor(tiles, projection).map((tile) => (
            <image
              key={tile.url}
              href={tile.url}
              x={tile.x}
              y={tile.y}
              width={tile.size}
              height={tile.size}
              preserveAspectRatio="none"
            />
          ))}
        </g>
      )}
      <g className="coastline" stroke="#8d6e63" strokeWidth={1}>
        {data.coastline.map((segment, i) => {
          const [a, b] = pairOf<LatLon>(segment, []);
          const [x1, y1] = at(a);
          const [x2, y2] = at(b);
          return <line key={i} x1={x1} y1={y1} x2={x2} y2={y2} />;
        })}
      </g>
      {data.charts.map((c) => (
        <polygon
          key={`chart-${c.id}`}
          data-chart={c.id}
          data-crossed={crossedAreas.has(c.id) ? "true" : undefined}
          points={points(c.polygon, at)}
          fill={CHART_COLOUR[c.kind ?? "other"] ?? CHART_COLOUR.other}
          fillOpacity={0.25}
          stroke={CHART_COLOUR[c.kind ?? "other"] ?? CHART_COLOUR.other}
          strokeWidth={crossedAreas.has(c.id) ? 3 : 1}
        >
          <title>{`${c.id}${c.title ? ` (${c.title})` : ""}: ${c.kind ?? "chart"}`}</title>
        </polygon>
      ))}
      {data.areas.map((a) => (
        <polygon
          key={`area-${a.id}`}
          data-area={a.id}
          points={points(a.polygon, at)}
          fill="#90caf9"
          fillOpacity={0.4}
          stroke="#1565c0"
          strokeWidth={crossedAreas.has(a.id) ? 3 : 1}
        >
          <title>{`${a.id}${a.title ? ` (${a.title})` : ""}`}</title>
        </polygon>
      ))}
      {data.legs.map((leg) => {
        const style = OUTCOME_STYLE[leg.outcome as keyof typeof OUTCOME_STYLE] ?? {
          letter: "?",
          colour: "#000",
        };
        const [x1, y1] = at(leg.start);
        const [x2, y2] = at(leg.end);
        const hit = crossed.has(`${leg.goal} ${leg.outcome}`);
        return (
          <g
            key={`${leg.goal}-${leg.outcome}-${leg.to}`}
            className={hit ? "leg leg-crossing" : "leg"}
            data-leg={`${leg.goal} ${leg.outcome}`}
          >
            <line
              x1={x1}
              y1={y1}
              x2={x2}
              y2={y2}
              stroke={hit ? "#d50000" : style.colour}
              strokeWidth={hit ? 4 : 1.5}
              strokeDasharray={leg.outcome === "succeed" ? undefined : "5 3"}
            />
            <text x={(x1 + x2) / 2} y={(y1 + y2) / 2} fontSize={11} fill={style.colour}>
              {style.letter}
            </text>
            <title>{`${leg.goal} ${leg.outcome} → ${leg.to}: ${Math.round(leg.length_m)} m`}</title>
          </g>
        );
      })}
    </svg>
  );
}

/** The plan view of given orders (the draft in the editor, the version under review). */
export function ChartPlanView({ orders }: { orders: Schema<"Orders"> }) {
  const { data, error, loading } = useLoad(
    async () => unwrap(await api.POST("/api/plan-view", { body: orders })),
    [JSON.stringify(orders)],
  );
  // The server's tile setting; without it (or if it cannot be read) no tile is requested.
  const config = useLoad(async () => unwrap(await api.GET("/api/client-config")), []);
  const tiles = config.data?.map_tiles ?? null;
  if (loading && !data) return <Loading what="the plan view" />;
  if (!data) return <ErrorMessage error={error ?? "The plan view could not be drawn."} />;
  return (
    <div className="chart-plan-view">
      {config.loading && !config.data ? (
        <Loading what="the map settings" />
      ) : (
        <PlanSvg data={data} tiles={tiles} />
      )}
      <p>
        Legs: <span style={{ color: OUTCOME_STYLE.succeed.colour }}>s succeed</span>,{" "}
        <span style={{ color: OUTCOME_STYLE.fail.colour }}>f fail</span>,{" "}
        <span style={{ color: OUTCOME_STYLE.violate.colour }}>c constraint</span>; crossings in
        red.{" "}
        {tiles
          ? `Map tiles: ${config.data?.map_tiles_attribution || new URL(tiles.replace(/[{}]/g, "")).host}.`
          : "No map tiles are loaded; the coastline is the server's land mask."}
      </p>
      {data.crossings.length > 0 ? (
        <ul className="plan-crossings" aria-label="Crossings">
          {data.crossings.map((c, i) => (
            <li key={i}>{c.message}</li>
          ))}
        </ul>
      ) : (
        <p className="plan-no-crossings">No leg, sweep or loiter crosses a forbidden area.</p>
      )}
    </div>
  );
}
