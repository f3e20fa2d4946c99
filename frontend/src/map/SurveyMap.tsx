/** The "Plan survey" dialog's map: the draft's areas, those the plan chose highlighted, and the
 * planned route (start, each area's entry and exit, recovery) labelled step by step. */
import { useMemo } from "react";

import type { Orders } from "../editor/graph";
import type { PlanOverlay } from "../editor/panels";
import { type MapArea } from "./features";
import { orderMapAreas } from "./orderAreas";
import { ChartMap } from "./LazyChartMap";

export function SurveyMap({ orders, overlay, title }: { orders: Orders; overlay: PlanOverlay | null; title: string }) {
  const source = orders.areas;
  const list = useMemo(
    (): MapArea[] =>
      orderMapAreas(orders, (id) => ({ chosen: overlay?.chosen.includes(id) ?? false })),
    // eslint-disable-next-line react-hooks/exhaustive-deps -- only the areas and the plan matter
    [source, overlay],
  );
  const route = useMemo(() => overlay?.route ?? [], [overlay]);
  return (
    <div className="survey-map">
      {overlay && overlay.route.length > 1 && (
        <p className="hint" data-testid="plan-route">
          Route: {overlay.route.map((r) => r.label).join(" → ")}
        </p>
      )}
      <ChartMap
        label={title}
        testId="survey-map"
        areas={list}
        route={route}
        fitKey={`${list.map((a) => a.id).join(",")}|${route.length}`}
      />
    </div>
  );
}
