/**
 * The areas chart of the mission editor: every area on the map, the selected one with numbered
 * vertex handles (drag to move), and "Add vertices by clicking" that adds a vertex exactly where
 * the map is clicked. Typed vertices are drawn at once: the map redraws from the orders.
 */
import { useMemo, useState } from "react";

import type { Orders } from "../editor/graph";
import { type LatLon, type MapArea } from "./features";
import { orderMapAreas } from "./orderAreas";
import { ChartMap } from "./LazyChartMap";

export function AreaChart({
  orders,
  selected,
  onSelect,
  onAddVertex,
  onMoveVertex,
}: {
  orders: Orders;
  selected: string | null;
  onSelect: (id: string) => void;
  onAddVertex: (area: string, at: LatLon) => void;
  onMoveVertex: (area: string, index: number, at: LatLon) => void;
}) {
  const [adding, setAdding] = useState(false);
  const source = orders.areas;
  const list = useMemo(
    (): MapArea[] =>
      orderMapAreas(orders, (id) => ({ selected: id === selected })),
    // eslint-disable-next-line react-hooks/exhaustive-deps -- only the areas matter here
    [source, selected],
  );
  const fitKey = list.map((a) => `${a.id}:${a.polygon.length > 0 ? 1 : 0}`).join(",");
  return (
    <div className="area-chart">
      {selected && (
        <button type="button" aria-pressed={adding} onClick={() => setAdding((a) => !a)}>
          {adding ? `Stop adding vertices to ${selected}` : `Add vertices to ${selected} by clicking`}
        </button>
      )}
      <ChartMap
        label="Chart of the areas"
        testId="area-chart"
        areas={list}
        selected={selected}
        onSelect={onSelect}
        onAddVertex={adding && selected ? (at) => onAddVertex(selected, at) : null}
        onMoveVertex={onMoveVertex}
        fitKey={fitKey}
      />
    </div>
  );
}
