/**
 * What the panels beside the graph share (each panel is its own file: MissionPanel, AreasPanel,
 * QuantitiesPanel, VehiclePanel, NormsPanel): the edit they apply and the finding markers shown
 * beside their fields. Every control is a labelled input; ids, lists and multi-line specs commit
 * on Enter or when focus leaves them.
 */
import type { Orders } from "./graph";

export type { PlanOverlay } from "./AreasPanel";

export type EditOrders = (change: (o: Orders) => Orders, group?: string) => void;
export type Markers = Map<string, { codes: string[]; severity: "error" | "warning" }>;

export function MarkerBadge({ markers, id }: { markers: Markers; id: string }) {
  const mark = markers.get(id);
  if (!mark) return null;
  return (
    <span className={`badge ${mark.severity === "error" ? "bad" : "warn"}`} data-testid={`field-markers-${id}`}>
      {mark.severity === "error" ? "✖ " : "⚠ "}
      {mark.codes.join(" ")}
    </span>
  );
}
