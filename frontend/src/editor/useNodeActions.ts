/** The toolbar's node actions: add a goal or a terminal, delete the selection, auto layout. */
import { useReactFlow } from "@xyflow/react";
import { type RefObject, useCallback } from "react";

import { addGoal, addTerminal, deleteNodes, disconnect, type Outcome } from "./graph";
import { canvasAspect, layoutOffThread } from "./layoutClient";
import { placeNew } from "./placeNew";
import { defaultReturn, setReturns } from "./scope";
import { useEditorApi } from "./store";
import type { Editing } from "./useEditing";
import type { OpenView } from "./useOpenView";

export interface NodeActions {
  addGoalNode: () => void;
  addTerminalNode: (kind: "complete" | "abort") => void;
  deleteSelected: () => void;
  relayout: () => Promise<void>;
}

export function useNodeActions(editing: Editing, open: OpenView, selectWhenShown: (ids: string[]) => void, titleRef: RefObject<HTMLInputElement | null>): NodeActions {
  const flow = useReactFlow();
  const store = useEditorApi();
  const { latestScoped: latest, edit } = editing;
  const addGoalNode = useCallback(() => {
    const at = placeNew(flow, store.getState().nodes, latest().layout);
    const { orders: next, id } = addGoal(latest().orders);
    selectWhenShown([id]);
    edit((d) => ({ orders: next, layout: { ...d.layout, [id]: at } }));
    window.setTimeout(() => titleRef.current?.select(), 50);
  }, [flow, store, latest, edit, selectWhenShown, titleRef]);
  const addTerminalNode = useCallback(
    (kind: "complete" | "abort") => {
      const at = placeNew(flow, store.getState().nodes, latest().layout);
      const added = addTerminal(latest().orders, kind);
      const id = added.id;
      // A refinement's terminal returns one of the parent goal's outcomes.
      const next = latest().refinement ? setReturns(added.orders, id, defaultReturn(kind)) : added.orders;
      selectWhenShown([id]);
      edit((d) => ({ orders: next, layout: { ...d.layout, [id]: at } }));
    },
    [flow, store, latest, edit, selectWhenShown],
  );
  const deleteSelected = useCallback(() => {
    const { nodes: ns, edges: es } = store.getState();
    const nodeIds = ns.filter((n) => n.selected).map((n) => n.id);
    const edgeList = es.filter((e) => e.selected);
    if (nodeIds.length === 0 && edgeList.length === 0) return;
    edit((d) => {
      let o = deleteNodes(d.orders, nodeIds);
      for (const e of edgeList) o = disconnect(o, e.source, e.sourceHandle as Outcome, e.target);
      const layout = { ...d.layout };
      for (const id of nodeIds) delete layout[id];
      return { orders: o, layout };
    });
  }, [store, edit]);
  const relayout = useRelayout(editing, open);
  return { addGoalNode, addTerminalNode, deleteSelected, relayout };
}

/** Auto layout: the canvas says ready when the new positions are shown (tests wait for it). */
function useRelayout(editing: Editing, open: OpenView): () => Promise<void> {
  const flow = useReactFlow();
  const store = useEditorApi();
  const { latestScoped: latest, edit } = editing;
  const { showLaidOutThenReady, fitWhenPlaced } = open;
  return useCallback(async () => {
    const { showReady, failed } = store.getState();
    showReady(false);
    const sizes: Record<string, { width: number; height: number }> = {};
    for (const n of flow.getNodes()) {
      if (n.measured?.width && n.measured.height) sizes[n.id] = { width: n.measured.width, height: n.measured.height };
    }
    let layout;
    try {
      layout = await layoutOffThread(latest().orders, sizes, canvasAspect());
    } catch (e) {
      failed(e);
      showReady(true);
      return;
    }
    // A layout equal to the one shown changes no node: fit (and say ready) at once.
    const shown = latest().layout;
    if (Object.entries(layout).every(([id, p]) => shown[id]?.x === p.x && shown[id]?.y === p.y)) {
      showLaidOutThenReady();
      return;
    }
    fitWhenPlaced();
    edit((d) => ({ ...d, layout }));
  }, [flow, store, latest, edit, showLaidOutThenReady, fitWhenPlaced]);
}
