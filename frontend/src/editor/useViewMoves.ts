/** Moves of the view the operator asks for: go to a node, focus a goal's neighbourhood, show a
 * finding's subjects (and its counterexample path highlighted). */
import { useReactFlow } from "@xyflow/react";
import { useCallback } from "react";

import type { Finding } from "../api/client";
import { findingPath, type PathLike } from "./graph";
import { GOAL_SIZE } from "./layout";
import { FIT, GOTO_ZOOM, MIN_ZOOM } from "./canvas";
import { useEditorApi } from "./store";
import type { Editing } from "./useEditing";

export interface ViewMoves {
  goTo: (id: string) => void;
  focusOn: (id: string | null) => void;
  pickFinding: (f: Finding, given?: string[]) => void;
  highlightPath: (path: PathLike | null, label?: string) => void;
}

export function useViewMoves(editing: Editing): ViewMoves {
  const flow = useReactFlow();
  const store = useEditorApi();
  const { latestScoped } = editing;
  const goTo = useCallback(
    (id: string) => {
      const node = store.getState().nodes.find((n) => n.id === id);
      if (!node) return store.getState().announce(`No node ${id}.`);
      store.getState().select([id]);
      // At one zoom whatever the zoom was: kept at a new draft's fit (1.2), a 1024 px canvas showed
      // the node's successor mostly under the inspector, and a wire dragged to it auto-panned.
      void flow.setCenter(node.position.x + GOAL_SIZE.width / 2, node.position.y + GOAL_SIZE.height / 2, { zoom: GOTO_ZOOM });
    },
    [flow, store],
  );
  // "Focus this goal": its predecessors and successors in view, the rest faded (useFlowElements).
  const focusOn = useCallback(
    (id: string | null) => {
      store.getState().focusGoal(id);
      if (!id) return void flow.fitView(FIT);
      const near = new Set([id]);
      for (const e of store.getState().edges) {
        if (e.source === id) near.add(e.target);
        if (e.target === id) near.add(e.source);
      }
      void flow.fitView({ nodes: [...near].map((n) => ({ id: n })), padding: 0.25, maxZoom: 1, minZoom: MIN_ZOOM });
    },
    [flow, store],
  );
  const highlightPath = useCallback((path: PathLike | null, label = "") => store.getState().showHighlight(path ? { path, label } : null), [store]);
  const pickFinding = useCallback(
    (f: Finding, given: string[] = f.subjects) => {
      const prefix = latestScoped().prefix;
      const subjects = prefix === "" ? given : given.filter((s) => s.startsWith(prefix)).map((s) => s.slice(prefix.length).split("/")[0]!);
      store.getState().select(subjects);
      const shown = new Set(store.getState().nodes.map((n) => n.id));
      const inView = subjects.filter((id) => shown.has(id));
      if (inView.length > 0) void flow.fitView({ nodes: inView.map((id) => ({ id })), padding: 0.5, maxZoom: 1 });
      const path = findingPath(f);
      highlightPath(path, path ? `${f.code} counterexample` : "");
    },
    [flow, store, latestScoped, highlightPath],
  );
  return { goTo, focusOn, pickFinding, highlightPath };
}
