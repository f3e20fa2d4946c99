/** Where a new node goes: free space beside the selected node, else near the centre of the view,
 * kept in view (the zoom stays as it is). */
import type { Node, ReactFlowInstance } from "@xyflow/react";

import type { Layout } from "./graph";
import { freePlace } from "./canvas";

export function placeNew(flow: ReactFlowInstance, nodes: Node[], layout: Layout): { x: number; y: number } {
  const pane = document.querySelector(".editor-canvas")?.getBoundingClientRect();
  const centre = pane ? flow.screenToFlowPosition({ x: pane.left + pane.width / 2, y: pane.top + pane.height / 2 }) : { x: 0, y: 0 };
  const sizes: Record<string, { width: number; height: number }> = {};
  let selected: { x: number; y: number } | null = null;
  for (const n of nodes) {
    if (n.measured?.width && n.measured.height) sizes[n.id] = { width: n.measured.width, height: n.measured.height };
    if (n.selected && !selected) selected = n.position;
  }
  const at = freePlace(layout, sizes, selected, centre);
  if (pane) {
    const corner = flow.flowToScreenPosition(at);
    const far = flow.flowToScreenPosition({ x: at.x + 220, y: at.y + 112 });
    if (corner.x < pane.left || corner.y < pane.top || far.x > pane.right || far.y > pane.bottom) {
      void flow.setCenter(at.x + 110, at.y + 56, { zoom: flow.getZoom() });
    }
  }
  return at;
}
