/** The dialog shown when someone else saved the draft meanwhile (a 412 on save). */
import { useEffect, useRef } from "react";

import type { MissionDetail } from "../api/client";

export interface Conflict {
  theirs: MissionDetail;
  differences: string[];
}

export function ConflictDialog({ conflict, onReload, onKeepMine }: { conflict: Conflict; onReload: () => void; onKeepMine: () => void }) {
  const first = useRef<HTMLButtonElement>(null);
  useEffect(() => first.current?.focus(), []);
  return (
    <div className="dialog-backdrop">
      <div role="alertdialog" aria-modal="true" aria-labelledby="conflict-title" aria-describedby="conflict-text" className="dialog">
        <h3 id="conflict-title">Someone else saved this draft</h3>
        <p id="conflict-text">
          {conflict.theirs.updated_by} saved revision {conflict.theirs.revision} while you were editing. Nothing was
          overwritten. Differences between your version and theirs:
        </p>
        <ul data-testid="conflict-differences">
          {conflict.differences.length === 0 ? <li>Only node positions differ.</li> : conflict.differences.map((d) => <li key={d}>{d}</li>)}
        </ul>
        <div className="actions">
          <button type="button" ref={first} onClick={onReload}>
            Reload theirs
          </button>
          <button type="button" className="danger" onClick={onKeepMine}>
            Keep mine (overwrite theirs)
          </button>
        </div>
      </div>
    </div>
  );
}
