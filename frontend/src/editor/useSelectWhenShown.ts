/** Selects what was just added or pasted once its nodes exist (the inspector then shows it). */
import { useCallback, useEffect, useRef } from "react";

import { useEditor } from "./store";

export function useSelectWhenShown(): (ids: string[]) => void {
  const nodes = useEditor((s) => s.nodes);
  const select = useEditor((s) => s.select);
  const wantedRef = useRef<string[] | null>(null);
  useEffect(() => {
    const wanted = wantedRef.current;
    if (wanted && wanted.every((id) => nodes.some((n) => n.id === id))) {
      wantedRef.current = null;
      select(wanted);
    }
  }, [nodes, select]);
  return useCallback((ids: string[]) => void (wantedRef.current = ids), []);
}
