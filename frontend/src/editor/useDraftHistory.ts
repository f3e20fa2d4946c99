/** The editor's draft (orders and layout) under undo/redo (history.ts), kept in the store. */
import { useCallback } from "react";

import type { History } from "./history";
import { type Draft, useEditor, useEditorApi } from "./store";

export { type Draft, isLaidOut } from "./store";

export interface DraftHistory {
  history: History<Draft>;
  /** The newest draft, as set (not as React last rendered it), so that an edit can be sent to
   * the server from its event handler. */
  latest: () => Draft;
  updateHistory: (update: (h: History<Draft>) => History<Draft>) => void;
}

export function useDraftHistory(): DraftHistory {
  const store = useEditorApi();
  const history = useEditor((s) => s.history);
  const latest = useCallback(() => store.getState().history.present, [store]);
  const updateHistory = useCallback((update: (h: History<Draft>) => History<Draft>) => store.getState().setHistory(update), [store]);
  return { history, latest, updateHistory };
}
