/**
 * The dialog shown when someone else saved the draft meanwhile and some of their edits overlap
 * mine (the same field of one item, or one side deleted what the other changed). What did not
 * overlap is already merged (merge.ts); each overlapping item is shown side by side, with a
 * choice of version per item. Nothing is lost: the choice is an undoable edit.
 */
import { useEffect, useRef, useState } from "react";

import type { MissionDetail } from "../api/client";
import type { MergeConflict, MergeResult, Side } from "./merge";

export interface Conflict {
  theirs: MissionDetail;
  differences: string[];
  merge: MergeResult;
}

function shown(value: unknown): string {
  return value === undefined ? "(deleted)" : JSON.stringify(value, null, 2);
}

function Item({ conflict, side, onChoose }: { conflict: MergeConflict; side: Side; onChoose: (side: Side) => void }) {
  const name = `conflict-${conflict.key}`;
  return (
    <fieldset className="conflict-item" data-testid={`conflict-item-${conflict.key}`}>
      <legend>
        {conflict.label}
        {conflict.fields.length > 0 ? `: both changed ${conflict.fields.join(", ")}` : ": deleted on one side, changed on the other"}
      </legend>
      <div className="conflict-sides">
        {(["mine", "theirs"] as const).map((s) => (
          <label key={s} className={`conflict-side${side === s ? " chosen" : ""}`}>
            <span>
              <input type="radio" name={name} checked={side === s} onChange={() => onChoose(s)} /> {s === "mine" ? "Keep yours" : "Keep theirs"}
            </span>
            <pre data-testid={`conflict-${s}-${conflict.key}`}>{shown(s === "mine" ? conflict.mine : conflict.theirs)}</pre>
          </label>
        ))}
      </div>
    </fieldset>
  );
}

export function ConflictDialog({
  conflict,
  onReload,
  onResolve,
}: {
  conflict: Conflict;
  onReload: () => void;
  onResolve: (choices: Record<string, Side>) => void;
}) {
  const first = useRef<HTMLButtonElement>(null);
  useEffect(() => first.current?.focus(), []);
  const [choices, setChoices] = useState<Record<string, Side>>(() => Object.fromEntries(conflict.merge.conflicts.map((c) => [c.key, "mine"])));
  const { merge } = conflict;
  return (
    <div className="dialog-backdrop">
      <div role="alertdialog" aria-modal="true" aria-labelledby="conflict-title" aria-describedby="conflict-text" className="dialog conflict-dialog">
        <h3 id="conflict-title">Someone else saved this draft</h3>
        <p id="conflict-text">
          {conflict.theirs.updated_by} saved revision {conflict.theirs.revision} while you were editing. Nothing was
          overwritten. {merge.merged.length > 0 ? "Merged by themselves: " : ""}
        </p>
        {merge.merged.length > 0 && (
          <ul data-testid="conflict-merged">
            {merge.merged.map((d) => (
              <li key={d}>{d}</li>
            ))}
          </ul>
        )}
        <p>Both of you changed these; choose a version of each:</p>
        <div data-testid="conflict-differences">
          {merge.conflicts.map((c) => (
            <Item key={c.key} conflict={c} side={choices[c.key] ?? "mine"} onChoose={(side) => setChoices((all) => ({ ...all, [c.key]: side }))} />
          ))}
        </div>
        <div className="actions">
          <button type="button" ref={first} onClick={() => onResolve(choices)}>
            Apply these choices
          </button>
          <button type="button" className="danger" onClick={onReload}>
            Discard mine, reload theirs
          </button>
        </div>
      </div>
    </div>
  );
}
