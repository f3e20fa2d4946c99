/**
 * Autosave and conflict: every change of the present draft (edit, undo, redo) is checked and
 * saved with If-Match (discrete edits at once, from the event handler; typing after a short
 * pause). A 412 opens the conflict; nothing is overwritten until the operator chooses.
 */
import { useCallback, useEffect, useRef } from "react";

import type { MissionDetail } from "../api/client";
import { useDraftSaves } from "../api/missions";
import { describeDifferences, type Layout, type Orders } from "./graph";
import { push, reset } from "./history";
import { mergeOrders, resolveMerge, type Side } from "./merge";
import { refusalOf } from "./refusal";
import { type Draft, useEditorApi } from "./store";
import type { ServerCheck } from "./useServerCheck";

const SAVE_DELAY_MS = 250;

function mergedNotice(theirs: MissionDetail, merged: string[]): string {
  return `${theirs.updated_by} saved revision ${theirs.revision} meanwhile; merged with your edits${merged.length > 0 ? `: ${merged.join(" ")}` : "."}`;
}

export interface Autosave {
  /** Applies a change to the draft as one undo step (`group`: typing, coalesced) and saves it. */
  edit: (change: (d: Draft) => Draft, group?: string) => void;
  editOrders: (change: (o: Orders) => Orders, group?: string) => void;
  /** Checks and saves the present draft after it changed outside `edit` (undo, redo). */
  changed: (group?: string) => void;
  save: () => Promise<void>;
  /** Saves positions computed on open, once, unless the draft opened with them all. */
  saveComputedLayout: (layout: Layout) => void;
  reloadTheirs: () => void;
  /** Applies the conflict dialog's choice per overlapping item to the merged orders and saves. */
  resolve: (choices: Record<string, Side>) => void;
}

// Length: save, merge and conflict share the in-flight save's refs.
export function useAutosave(mission: MissionDetail, onReloaded: (theirs: MissionDetail) => void, server: ServerCheck): Autosave {
  const store = useEditorApi();
  // Each save updates the query cache itself (api/missions.ts): the page shows it without re-reading.
  const { saveDraft, saveLayout } = useDraftSaves(mission.id);
  const { check, refreshChecks } = server;
  const saving = useRef(false);
  const again = useRef(false);
  const latest = useCallback(() => store.getState().history.present, [store]);
  const inConflict = useCallback(() => store.getState().conflict !== null, [store]);

  /** Someone else saved meanwhile: merges their orders with mine (three-way, against the
   * revision both started from). Returns whether the merged draft should be saved at once (no
   * overlap); otherwise the conflict dialog asks per item. */
  const mergeTheirs = useCallback(
    (theirs: MissionDetail): boolean => {
      const { base, conflictFound, showNotice } = store.getState();
      const merge = mergeOrders(base, latest().orders, theirs.orders);
      if (merge.conflicts.length > 0) {
        const differences = describeDifferences(latest().orders, theirs.orders);
        conflictFound({ theirs, differences, merge });
        return false;
      }
      adoptMerged(theirs, merge.orders);
      showNotice(mergedNotice(theirs, merge.merged));
      return true;
    },
    [store, latest],
  );
  /** Takes merged orders as a new undo step, on top of their revision (mine positions first). */
  const adoptMerged = useCallback(
    (theirs: MissionDetail, orders: Orders) => {
      const { setHistory, mergedOnto } = store.getState();
      setHistory((h) => push(h, { orders, layout: { ...theirs.layout, ...h.present.layout } }));
      mergedOnto(theirs.revision, theirs.orders);
      void check(orders);
    },
    [store, check],
  );

  // A save sends what changed: the orders (If-Match; a new revision) and, apart, the positions
  // (editor data: no revision, no "Updated by").
  const save = useCallback(async () => {
    const { saveStarted, ordersSaved, layoutSaved, saveFinished, saveRefused } = store.getState();
    if (saving.current) {
      again.current = true;
      return;
    }
    saving.current = true;
    saveStarted();
    const sent = latest();
    try {
      if (sent.orders !== store.getState().base) {
        // Saved once checked: the save then finds the report cached instead of validating the
        // same orders a second time beside the check.
        const reported = await check(sent.orders);
        const answer = await saveDraft({ revision: store.getState().revision, orders: sent.orders });
        if (answer.theirs) {
          again.current = mergeTheirs(answer.theirs);
          return;
        }
        ordersSaved(answer.saved.revision, sent.orders);
        // The check above reported these orders; re-read the report only if it failed.
        if (!reported && latest() === sent) await refreshChecks();
      }
      if (sent.layout !== store.getState().savedLayout) {
        await saveLayout(sent.layout);
        layoutSaved(sent.layout);
      }
      saveFinished(latest() === sent);
    } catch (e) {
      saveRefused(e, refusalOf(e, sent.orders));
    } finally {
      saving.current = false;
      if (again.current) {
        again.current = false;
        void save();
      }
    }
  }, [store, latest, saveDraft, saveLayout, refreshChecks, check, mergeTheirs]);

  const saveTimer = useRef<number | undefined>(undefined);
  useEffect(() => () => window.clearTimeout(saveTimer.current), []);
  const changed = useCallback(
    (group?: string) => {
      store.getState().edited();
      performance.mark("editor:edit");
      if (inConflict()) return;
      window.clearTimeout(saveTimer.current);
      store.getState().savePending();
      if (group) {
        saveTimer.current = window.setTimeout(() => void save(), SAVE_DELAY_MS);
        return;
      }
      void check(latest().orders);
      void save();
    },
    [store, save, check, latest, inConflict],
  );

  const edit = useCallback(
    (change: (d: Draft) => Draft, group?: string) => {
      store.getState().setHistory((h) => push(h, change(h.present), group ? { group } : {}));
      changed(group);
    },
    [store, changed],
  );
  const editOrders = useCallback(
    (change: (o: Orders) => Orders, group?: string) => edit((d) => ({ ...d, orders: change(d.orders) }), group),
    [edit],
  );

  const opened = useRef(mission.layout);
  const saveComputedLayout = useCallback(
    (layout: Layout) => {
      if (inConflict() || Object.keys(layout).every((id) => opened.current[id])) return;
      store.getState().savePending();
      void save();
    },
    [store, save, inConflict],
  );

  const reloadTheirs = useCallback(() => {
    const { conflict, theirsReloaded, setHistory } = store.getState();
    if (!conflict) return;
    setHistory(reset({ orders: conflict.theirs.orders, layout: conflict.theirs.layout }));
    theirsReloaded(conflict.theirs);
    void refreshChecks();
    onReloaded(conflict.theirs);
  }, [store, refreshChecks, onReloaded]);

  const resolve = useCallback(
    (choices: Record<string, Side>) => {
      const { conflict, showNotice } = store.getState();
      if (!conflict) return;
      const orders = resolveMerge(conflict.merge, choices);
      const mine = conflict.merge.conflicts.filter((c) => choices[c.key] === "mine").map((c) => c.label);
      adoptMerged(conflict.theirs, orders);
      showNotice(
        `${mergedNotice(conflict.theirs, conflict.merge.merged)} Overlapping edits: ${
          mine.length > 0 ? `yours kept for ${mine.join(", ")}` : "theirs kept"
        }${mine.length > 0 && mine.length < conflict.merge.conflicts.length ? ", theirs for the rest" : ""}. Undo brings your version back.`,
      );
      void save();
    },
    [store, adoptMerged, save],
  );

  return { edit, editOrders, changed, save, saveComputedLayout, reloadTheirs, resolve };
}
