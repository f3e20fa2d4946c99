/** The canvas's keyboard shortcuts (Shortcuts.tsx lists them). They act only while focus is in
 * the canvas, not in the inspector's fields. */
import { type KeyboardEvent, useCallback } from "react";

import { goals } from "./graph";
import { useEditorApi } from "./store";
import type { EditorActions } from "./useEditorActions";
import { scopedDraft } from "./useScopedDraft";

type Shortcut = (event: KeyboardEvent<HTMLDivElement>) => boolean;

export function useCanvasKeys(actions: EditorActions): (event: KeyboardEvent<HTMLDivElement>) => void {
  const store = useEditorApi();
  return useCallback(
    (event: KeyboardEvent<HTMLDivElement>) => {
      if ((event.target as HTMLElement).closest("input, textarea, select")) return;
      const { nodes, scope, focus, history } = store.getState();
      const selected = nodes.filter((n) => n.selected).map((n) => n.id);
      const selectedId = selected.length === 1 ? selected[0] : undefined;
      const refines = goals(scopedDraft(history.present, scope).orders).find((g) => g.id === selectedId)?.refines;
      const mod = event.ctrlKey || event.metaKey;
      const plain = !mod && !event.altKey;
      const key = event.key.toLowerCase();
      const shortcuts: [Shortcut, () => unknown][] = [
        [() => mod && key === "z" && !event.shiftKey, actions.doUndo],
        [() => mod && (key === "y" || (key === "z" && event.shiftKey)), actions.doRedo],
        [() => event.key === "Delete" || event.key === "Backspace", actions.deleteSelected],
        [() => mod && key === "c", actions.copySelected],
        [() => mod && key === "v", actions.pasteSelected],
        [() => mod && key === "d", actions.duplicateSelected],
        [() => plain && key === "g", actions.addGoalNode],
        [() => plain && key === "l", () => void actions.relayout()],
        [() => plain && key === "f" && selectedId !== undefined, () => actions.focusOn(selectedId ?? null)],
        [() => plain && key === "o" && Boolean(refines) && selectedId !== undefined, () => actions.openRefinement(selectedId!)],
        [() => plain && key === "u" && scope.path.length > 0, () => actions.openScope({ member: scope.member, path: scope.path.slice(0, -1) })],
        [() => event.key === "Escape" && focus !== null, () => actions.focusOn(null)],
        [() => event.key === "?", () => actions.dialogs.showShortcuts(true)],
      ];
      const found = shortcuts.find(([matches]) => matches(event));
      if (!found) return;
      found[1]();
      event.preventDefault();
    },
    [store, actions],
  );
}
