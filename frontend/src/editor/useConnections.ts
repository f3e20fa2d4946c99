/** Wiring on the canvas: a connection checked against the newest orders (refused with a reason
 * spoken by the live region), dropped on a node's body as on its input, and dragged positions. */
import type { Connection, Edge, FinalConnectionState, Node } from "@xyflow/react";
import { type RefObject, useCallback, useState } from "react";

import { checkConnection, connect } from "./graph";
import { trackConnectPointer } from "./canvas";
import { useEditorApi } from "./store";
import type { Editing } from "./useEditing";

export function useConnections(editing: Editing, canvasRef: RefObject<HTMLDivElement | null>) {
  const store = useEditorApi();
  const { latestScoped: latest, edit, editOrders } = editing;
  const onConnect = useCallback(
    (c: Connection) => {
      const { announce } = store.getState();
      const result = connect(latest().orders, c.source, c.sourceHandle ?? "", c.target);
      if (!result.check.ok) return announce(result.check.reason ?? "That connection is not allowed.");
      announce(`Connected ${c.source} ${c.sourceHandle} to ${c.target}.`);
      // Applied to the newest orders (a previous edit may not have rendered yet).
      editOrders((o) => connect(o, c.source, c.sourceHandle ?? "", c.target).orders);
    },
    [editOrders, latest, store],
  );
  const onConnectEnd = useCallback(
    (event: MouseEvent | TouchEvent, state: FinalConnectionState) => {
      if (state.isValid || !state.fromNode || !state.fromHandle?.id || state.fromHandle.type !== "source") return;
      const point = "changedTouches" in event ? event.changedTouches[0] : event;
      if (!point) return;
      // The topmost element under the pointer: a node hidden by the inspector or a menu is not hit.
      const hit = document.elementFromPoint(point.clientX, point.clientY)?.closest(".editor-canvas .react-flow__node");
      const target = hit?.getAttribute("data-id");
      if (!target || target === state.fromNode.id) return;
      onConnect({ source: state.fromNode.id, sourceHandle: state.fromHandle.id, target, targetHandle: "in" });
    },
    [onConnect],
  );
  const [pointer] = useState(() => trackConnectPointer(() => canvasRef.current));
  const isValidConnection = useCallback(
    (c: Connection | Edge) => pointer.inside() && checkConnection(latest().orders, c.source, c.sourceHandle, c.target).ok,
    [latest, pointer],
  );
  const onNodeDragStop = useCallback(
    (_event: unknown, _node: Node, dragged: Node[]) => {
      edit((d) => {
        const layout = { ...d.layout };
        for (const n of dragged) layout[n.id] = { x: Math.round(n.position.x), y: Math.round(n.position.y) };
        return { ...d, layout };
      });
    },
    [edit],
  );
  return { onConnect, onConnectStart: pointer.start, onConnectEnd, isValidConnection, onNodeDragStop };
}
