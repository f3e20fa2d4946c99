/** The draft's areas as map areas, styled by their contexts: one mapping for every map that
 * draws the orders (the areas chart marks the selected one, the survey map the chosen ones). */
import type { Orders } from "../editor/graph";
import { areas } from "../editor/model";
import { areaStyle, type MapArea } from "./features";

export function orderMapAreas(orders: Orders, mark: (id: string) => Partial<MapArea>): MapArea[] {
  return areas(orders).map((a) => ({
    id: a.id,
    title: a.title ?? null,
    source: "area",
    style: areaStyle(a.contexts ?? []),
    polygon: a.polygon ?? [],
    tags: a.contexts ?? [],
    ...mark(a.id),
  }));
}
