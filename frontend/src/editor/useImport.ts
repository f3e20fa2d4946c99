/** Import: the server reads the file (nothing stored); the draft is replaced by one ordinary
 * edit (undoable), laid out afresh, and saved with If-Match like any other. */
import { useCallback, useState } from "react";

import { plural } from "../format";
import { goals, type Orders } from "./graph";
import { readOrdersFile } from "../api/missions";
import { canvasAspect, layoutOffThread } from "./layoutClient";
import { openingScope } from "./scope";
import { useEditorApi } from "./store";
import type { Editing } from "./useEditing";

export function useImport(missionId: string, editing: Editing, fitWhenPlaced: () => void) {
  const store = useEditorApi();
  const editWhole = editing.autosave.edit;
  const [importing, setImporting] = useState(false);
  const importFile = useCallback(
    async (file: File) => {
      setImporting(true);
      try {
        const { orders: read, findings: found } = await readOrdersFile(file);
        const next: Orders = { ...read, id: missionId };
        const layout = await layoutOffThread(next, {}, canvasAspect());
        const { showReady, replaceScope, showNotice } = store.getState();
        showReady(false);
        fitWhenPlaced();
        replaceScope(openingScope(next));
        editWhole(() => ({ orders: next, layout }));
        const codes = [...new Set(found.map((f) => f.code).filter(Boolean))];
        const reading = codes.length > 0 ? `; reading it found ${codes.join(", ")}` : "";
        showNotice(`Imported ${file.name}: ${plural(goals(next).length, "goal")}${reading}. Undo brings the previous draft back.`);
      } finally {
        setImporting(false);
      }
    },
    [missionId, store, editWhole, fitWhenPlaced],
  );
  return { importFile, importing };
}
