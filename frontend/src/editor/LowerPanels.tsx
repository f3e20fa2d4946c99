/** The tabs below the canvas: the parts of the orders beside the graph (constraints, norms,
 * areas, quantities, vehicle, mission), the path explorer and the plain orders as saved. */
import { useMemo } from "react";

import { ErrorMessage } from "../components/Status";
import { Tabs } from "../components/Tabs";
import { knownQuantities } from "./expr";
import { ConstraintsPanel } from "./Inspector";
import { AreasPanel } from "./AreasPanel";
import { MissionPanel } from "./MissionPanel";
import { NormsPanel } from "./NormsPanel";
import { QuantitiesPanel } from "./QuantitiesPanel";
import { VehiclePanel } from "./VehiclePanel";
import { PathsPanel } from "./PathsPanel";
import { usePlainOrders } from "./queries";
import { useEditor } from "./store";
import type { EditorActions } from "./useEditorActions";
import type { Editing } from "./useEditing";
import type { FlowElements } from "./useFlowElements";

const PANELS = [
  { id: "editor-constraints", label: "Constraints" },
  { id: "editor-norms", label: "Norms" },
  { id: "editor-areas", label: "Areas" },
  { id: "editor-quantities", label: "Quantities" },
  { id: "editor-vehicle", label: "Vehicle" },
  { id: "editor-mission", label: "Mission" },
  { id: "editor-paths", label: "Path explorer" },
  { id: "editor-plain", label: "Plain orders" },
];

export function LowerPanels({ missionId, editing, actions, elements }: { missionId: string; editing: Editing; actions: EditorActions; elements: FlowElements }) {
  const panel = useEditor((s) => s.panel);
  const showPanel = useEditor((s) => s.showPanel);
  const report = useEditor((s) => s.report);
  const saveState = useEditor((s) => s.saveState);
  const revision = useEditor((s) => s.revision);
  const { panelOrders: orders, editPanelOrders: editOrders } = editing;
  const { markers, findings } = elements;
  const known = useMemo(() => knownQuantities(orders), [orders]);
  return (
    <div className="editor-lower">
      <Tabs label="Orders beside the graph" tabs={PANELS} selected={panel} onSelect={showPanel}>
        {panel === "editor-constraints" && <ConstraintsPanel orders={orders} editOrders={editOrders} markers={markers} findings={findings} />}
        {panel === "editor-norms" && <NormsPanel orders={orders} editOrders={editOrders} markers={markers} known={known} />}
        {panel === "editor-areas" && <AreasPanel orders={orders} editOrders={editOrders} markers={markers} />}
        {panel === "editor-quantities" && <QuantitiesPanel orders={orders} editOrders={editOrders} />}
        {panel === "editor-vehicle" && <VehiclePanel orders={orders} editOrders={editOrders} markers={markers} />}
        {panel === "editor-mission" && <MissionPanel orders={orders} editOrders={editOrders} />}
        {panel === "editor-paths" && (
          <PathsPanel missionId={missionId} orders={orders} report={report} revision={saveState === "saved" ? revision : null} onHighlight={actions.highlightPath} />
        )}
        {panel === "editor-plain" && <PlainOrders missionId={missionId} />}
      </Tabs>
    </div>
  );
}

/** The plain orders as saved: asked for while this tab is open, again after each save. */
function PlainOrders({ missionId }: { missionId: string }) {
  const plain = usePlainOrders(missionId, true);
  return (
    <section aria-labelledby="editor-plain-title" className="printable">
      <h3 id="editor-plain-title">Plain-language orders (as saved)</h3>
      <button type="button" onClick={() => window.print()}>
        Print orders
      </button>
      <ErrorMessage error={plain.error} />
      <pre className="orders-text" data-testid="editor-plain">
        {plain.data ?? ""}
      </pre>
    </section>
  );
}
