/**
 * What the canvas shows as it opens and after a layout: a draft without positions is laid out
 * (off the main thread, without an undo step); small orders open fitted to the canvas, large
 * ones at the start goal at a readable zoom, so that only the nodes in view are rendered
 * ("Zoom to fit" shows all). "ready" waits for the view to show the new positions (ready.ts).
 */
import { useReactFlow } from "@xyflow/react";
import { useCallback, useEffect, useRef } from "react";

import { reset } from "./history";
import { canvasAspect, layoutOffThread } from "./layoutClient";
import { readyWhenShown, showLaidOut } from "./ready";
import { isLaidOut, useEditor, useEditorApi } from "./store";
import { FIT } from "./canvas";
import type { Editing } from "./useEditing";
import { LARGE_GOALS } from "./useFlowElements";

export interface OpenView {
  /** Whether the draft opened large (over LARGE_GOALS goals): rendered only in view. */
  large: boolean;
  /** Shows the laid-out positions (fit, or the start goal when large), then says ready. */
  showLaidOutThenReady: () => void;
  /** Shows them once the nodes carry the positions of the edit about to be made. */
  fitWhenPlaced: () => void;
}

export function useOpenView(editing: Editing, openedGoals: number): OpenView {
  const flow = useReactFlow();
  const store = useEditorApi();
  const nodes = useEditor((s) => s.nodes);
  const ready = useEditor((s) => s.ready);
  const large = useRef(openedGoals > LARGE_GOALS);
  const openView = useRef(false);
  // A fit after a layout waits for the nodes to carry the new positions: a timer that fitted
  // after 150 ms came first on a loaded machine and fitted the old positions.
  const fitPending = useRef(false);
  const showLaidOutThenReady = useCallback(() => {
    void readyWhenShown(() => showLaidOut(flow, large.current, store.getState().nodes, FIT), store.getState().showReady);
  }, [flow, store]);
  useLayoutOnOpen(editing, () => (openView.current = true));
  useEffect(() => {
    performance.mark("editor:mounted");
  }, []);
  useEffect(() => {
    if (ready) performance.mark("editor:ready");
  }, [ready]);
  useEffect(() => {
    if (openView.current && nodes.length > 0) {
      openView.current = false;
      window.requestAnimationFrame(showLaidOutThenReady);
      return;
    }
    if (!fitPending.current) return;
    fitPending.current = false;
    window.requestAnimationFrame(showLaidOutThenReady);
  }, [nodes, showLaidOutThenReady]);
  const fitWhenPlaced = useCallback(() => void (fitPending.current = true), []);
  return { large: large.current, showLaidOutThenReady, fitWhenPlaced };
}

/** Lays out a draft that opened without positions, once; `placed` when positions are there. */
function useLayoutOnOpen(editing: Editing, placed: () => void): void {
  const store = useEditorApi();
  const { updateHistory, autosave } = editing;
  const { saveComputedLayout } = autosave;
  const laidOut = useRef(false);
  useEffect(() => {
    if (laidOut.current) return;
    laidOut.current = true;
    const { history, markPlaced } = store.getState();
    const draft = history.present;
    if (isLaidOut(draft)) {
      placed();
      saveComputedLayout(draft.layout); // a large draft laid out as it opened (store.ts)
      return;
    }
    void layoutOffThread(editing.view.orders, {}, canvasAspect()).then(
      (layout) => {
        placed();
        updateHistory((h) => reset({ ...h.present, layout: { ...layout, ...h.present.layout } }));
        markPlaced();
        saveComputedLayout(layout);
      },
      () => {
        placed();
        markPlaced(); // no layout: show the default positions rather than nothing
      },
    );
  }, [editing.view.orders, updateHistory, saveComputedLayout, store, placed]);
}
