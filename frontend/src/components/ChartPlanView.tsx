/**
 * Plan view of a mission's geography: areas, registry charts (styled by
 * kind), each outcome edge's leg (letter and colour of its outcome), the GEO crossings in red,
 * the coastline (Natural Earth land bundled with the app, plus the server's land-mask coastline
 * from /api/plan-view) on the same chart as the editor's, with a legend. Map tiles beneath only
 * when the server configures them (COUNTERSIGN_MAP_TILES, /api/client-config); otherwise none is
 * requested and it works offline. Every name is text, never markup.
 */
import { useMemo } from "react";

import type { Schema } from "../api/client";
import { type PlanData, useClientConfig, usePlanView } from "../api/plans";
import { areaStyle, type MapArea, type MapLeg } from "../map/features";
import { ChartMap } from "../map/LazyChartMap";
import { ErrorMessage, Loading } from "./Status";

/** POST /api/plan-view: what the plan view draws. */
export type { PlanData };

/** Areas and charts as the map draws them; a crossed one is outlined in red. */
export function planAreas(data: PlanData): MapArea[] {
  const crossed = new Set(data.crossings.map((c) => c.area).filter(Boolean));
  return [
    ...data.charts.map(
      (c): MapArea => ({
        id: c.id,
        title: c.title || null,
        source: "chart",
        style: areaStyle([c.kind, ...c.contexts]),
        polygon: c.polygon,
        crossed: crossed.has(c.id),
      }),
    ),
    ...data.areas.map(
      (a): MapArea => ({
        id: a.id,
        title: a.title || null,
        source: "area",
        style: areaStyle(a.contexts),
        polygon: a.polygon,
        tags: a.contexts,
        crossed: crossed.has(a.id),
      }),
    ),
  ];
}

export function planLegs(data: PlanData): MapLeg[] {
  const crossed = new Set(data.crossings.filter((c) => c.edge).map((c) => `${c.edge!.goal} ${c.edge!.outcome}`));
  return data.legs.map((l) => ({
    goal: l.goal,
    outcome: l.outcome,
    to: l.to,
    start: l.start,
    end: l.end,
    crossed: crossed.has(`${l.goal} ${l.outcome}`),
    lengthM: l.length_m,
  }));
}

/** The plan view of given orders (the draft in the editor, the version under review). */
export function ChartPlanView({ orders }: { orders: Schema<"Orders"> }) {
  const { data, error, isFetching: loading } = usePlanView(orders);
  // The server's tile setting; without it (or if it cannot be read) no tile is requested.
  const config = useClientConfig();
  const template = config.data?.map_tiles ?? null;
  const tiles = useMemo(
    () => (template ? { template, attribution: config.data?.map_tiles_attribution ?? "" } : null),
    [template, config.data?.map_tiles_attribution],
  );
  const areas = useMemo(() => (data ? planAreas(data) : []), [data]);
  const legs = useMemo(() => (data ? planLegs(data) : []), [data]);
  if (loading && !data) return <Loading what="the plan view" />;
  if (!data) return <ErrorMessage error={error ?? "The plan view could not be drawn."} />;
  return (
    <div className="chart-plan-view">
      {config.isPending ? (
        <Loading what="the map settings" />
      ) : (
        <ChartMap
          label="Plan view: areas, charts and legs"
          testId="plan-map"
          areas={areas}
          legs={legs}
          coastline={data.coastline}
          tiles={tiles}
          fitKey={`${areas.map((a) => a.id).join(",")}|${legs.length}`}
        />
      )}
      {!tiles && <p className="hint">No map tiles are loaded; the coastline is bundled with the app and the server's land mask.</p>}
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
