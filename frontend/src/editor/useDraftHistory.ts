/** The editor's draft (orders and layout) under undo/redo (history.ts). */
import { type RefObject, useCallback, useRef, useState } from "react";

import type { MissionDetail } from "../api/client";
import { goals, type Layout, type Orders, terminals } from "./graph";
import { createHistory, type History } from "./history";
import { ELK_MAX_GOALS, fastLayout } from "./layout";

export interface Draft {
  orders: Orders;
  layout: Layout;
}

/** Whether every goal and terminal of the draft has a position (an empty draft counts as not). */
export function isLaidOut(draft: Draft): boolean {
  const ids = [...goals(draft.orders).map((g) => g.id), ...terminals(draft.orders).map((t) => t.id)];
  return ids.length > 0 && ids.every((id) => draft.layout[id]);
}

export interface DraftHistory {
  history: History<Draft>;
  /** The newest history and draft, updated when they are set (not when React renders them), so
   * that an edit can be sent to the server from its event handler. */
  historyNow: RefObject<History<Draft>>;
  latest: RefObject<Draft>;
  updateHistory: (update: (h: History<Draft>) => History<Draft>) => void;
}

export function useDraftHistory(mission: MissionDetail): DraftHistory {
  // A large draft without positions is laid out at once (the linear-time layout), so that the
  // canvas never renders it unplaced; smaller ones wait for ELK before they render.
  const [history, setHistory] = useState<History<Draft>>(() => {
    performance.mark("editor:first-render");
    const opened = { orders: mission.orders as Orders, layout: (mission.layout ?? {}) as Layout };
    if (goals(opened.orders).length > ELK_MAX_GOALS && !isLaidOut(opened)) {
      opened.layout = { ...fastLayout(opened.orders), ...opened.layout };
    }
    return createHistory(opened);
  });
  const historyNow = useRef(history);
  const latest = useRef(history.present);
  const updateHistory = useCallback((update: (h: History<Draft>) => History<Draft>) => {
    const next = update(historyNow.current);
    historyNow.current = next;
    latest.current = next.present;
    setHistory(next);
  }, []);
  return { history, historyNow, latest, updateHistory };
}
