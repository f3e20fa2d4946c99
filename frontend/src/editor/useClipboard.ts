/** Copy, paste and duplicate of goals: clipboard JSON, also kept in localStorage so that a copy
 * reaches another mission when the system clipboard is not available. */
import { useCallback } from "react";

import { plural } from "../format";
import { copyGoals, pasteGoals, readClip } from "./model";
import { useEditorApi } from "./store";
import type { Editing } from "./useEditing";

const CLIP_KEY = "countersign.editor.clipboard";

export interface Clipboard {
  copySelected: () => void;
  pasteSelected: () => void;
  duplicateSelected: () => void;
}

function selectedIds(nodes: { id: string; selected?: boolean }[]): string[] {
  return nodes.filter((n) => n.selected).map((n) => n.id);
}

export function useClipboard(editing: Editing, selectWhenShown: (ids: string[]) => void): Clipboard {
  const store = useEditorApi();
  const { latestScoped: latest, edit } = editing;
  const copySelected = useCallback(() => {
    const clip = copyGoals(latest().orders, latest().layout, selectedIds(store.getState().nodes));
    if (!clip) return store.getState().announce("Select goals to copy.");
    const text = JSON.stringify(clip);
    try {
      window.localStorage.setItem(CLIP_KEY, text);
    } catch {
      /* storage full or disabled: the system clipboard may still work */
    }
    void navigator.clipboard?.writeText(text).catch(() => undefined);
    store.getState().announce(`Copied ${plural(clip.goals.length, "goal")}.`);
  }, [latest, store]);
  const pasteClip = useCallback(
    (text: string | null) => {
      const clip = readClip(text);
      if (!clip) return store.getState().announce("Nothing to paste: copy goals first.");
      const result = pasteGoals(latest().orders, latest().layout, clip);
      selectWhenShown(result.ids);
      edit(() => ({ orders: result.orders, layout: result.layout }));
      store.getState().announce(`Pasted ${result.ids.join(", ")}.`);
    },
    [latest, store, edit, selectWhenShown],
  );
  const pasteSelected = useCallback(() => {
    let text: string | null = null;
    try {
      text = window.localStorage.getItem(CLIP_KEY);
    } catch {
      text = null;
    }
    if (text) pasteClip(text);
    else void navigator.clipboard?.readText().then(pasteClip, () => pasteClip(null));
  }, [pasteClip]);
  const duplicateSelected = useCallback(() => {
    const clip = copyGoals(latest().orders, latest().layout, selectedIds(store.getState().nodes));
    if (clip) pasteClip(JSON.stringify(clip));
  }, [latest, store, pasteClip]);
  return { copySelected, pasteSelected, duplicateSelected };
}
