/**
 * Plan view of a mission's geography (issue 21): areas, registry charts, each outcome edge's
 * leg (letter and colour of its outcome), the GEO crossings highlighted, and the coastline from
 * the server's bundled land mask. Drawn as SVG from /api/plan-view: no map tiles, works offline.
 * Every name is React text, never markup.
 */
import { useLoad } from "../useLoad";
import { api, unwrap } from "../api/client";
import { ErrorMessage, Loading } from "./Status";

type LatLon = [number, number];
interface PlanLeg {
  goal: string;
  outcome: string;
  to: string;
  start: LatLon;
  end: LatLon;
  length_m: number;
}
interface PlanShape {
  id: string;
  title: string;
  kind?: string;
  contexts: string[];
  polygon: LatLon[];
}
interface PlanCrossing {
  subjects: string[];
  message: string;
  area?: string | null;
  edge?: { goal: string; outcome: string; to: string } | null;
}
export interface PlanData {
  areas: PlanShape[];
  charts: PlanShape[];
  legs: PlanLeg[];
  crossings: PlanCrossing[];
  coastline: [LatLon, LatLon][];
  box: [number, number, number, number] | null;
}

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

function projector(data: PlanData): (p: LatLon) => [number, number] {
  const points = [
    ...data.areas.flatMap((a) => a.polygon),
    ...data.legs.flatMap((l) => [l.start, l.end]),
  ];
  const lats = points.map((p) => p[0]);
  const lons = points.map((p) => p[1]);
  const [south, north] = lats.length ? [Math.min(...lats), Math.max(...lats)] : [-1, 1];
  const [west, east] = lons.length ? [Math.min(...lons), Math.max(...lons)] : [-1, 1];
  const cos = Math.cos((((south + north) / 2) * Math.PI) / 180);
  const spanX = Math.max((east - west) * cos, 1e-6);
  const spanY = Math.max(north - south, 1e-6);
  const scale = Math.min((WIDTH - 2 * PAD) / spanX, (HEIGHT - 2 * PAD) / spanY);
  return ([lat, lon]) => [
    PAD + (lon - west) * cos * scale + (WIDTH - 2 * PAD - spanX * scale) / 2,
    HEIGHT - PAD - (lat - south) * scale - (HEIGHT - 2 * PAD - spanY * scale) / 2,
  ];
}

function points(shape: LatLon[], at: (p: LatLon) => [number, number]): string {
  return shape.map((p) => at(p).map((v) => v.toFixed(1)).join(",")).join(" ");
}

export function PlanSvg({ data }: { data: PlanData }) {
  const at = projector(data);
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
      <g className="coastline" stroke="#8d6e63" strokeWidth={1}>
        {data.coastline.map(([a, b], i) => {
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
export function ChartPlanView({ orders }: { orders: unknown }) {
  const { data, error, loading } = useLoad(
    async () =>
      unwrap(
        await api.POST("/api/plan-view", { body: orders as Record<string, never> }),
      ) as unknown as PlanData,
    [JSON.stringify(orders)],
  );
  if (loading && !data) return <Loading what="the plan view" />;
  if (!data) return <ErrorMessage error={error ?? "The plan view could not be drawn."} />;
  return (
    <div className="chart-plan-view">
      <PlanSvg data={data} />
      <p>
        Legs: <span style={{ color: OUTCOME_STYLE.succeed.colour }}>s succeed</span>,{" "}
        <span style={{ color: OUTCOME_STYLE.fail.colour }}>f fail</span>,{" "}
        <span style={{ color: OUTCOME_STYLE.violate.colour }}>c constraint</span>; crossings in
        red. No map tiles are loaded; the coastline is the server&apos;s land mask.
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
