/**
 * The edits of one mounted editor: the draft under undo/redo, checked and saved (useAutosave,
 * useServerCheck), with the canvas's edits applied at the scope shown and the panels' edits at
 * the mission or team member. A saved draft updates the query cache (queries.ts).
 */
import { useQueryClient } from "@tanstack/react-query";
import { useCallback, useMemo } from "react";

import type { MissionDetail, Report } from "../api/client";
import type { Orders } from "./graph";
import { redo, undo } from "./history";
import { draftSaved } from "../api/missions";
import { ordersAt } from "./scope";
import { type Draft, useEditor, useEditorApi } from "./store";
import { type Autosave, useAutosave } from "./useAutosave";
import { type DraftHistory, useDraftHistory } from "./useDraftHistory";
import { applyAtMember, applyScoped, type ScopedDraft, scopedDraft, useScopedDraft } from "./useScopedDraft";
import { useServerCheck } from "./useServerCheck";

export type EditOrders = (change: (o: Orders) => Orders, group?: string) => void;

export interface Editing extends DraftHistory {
  autosave: Autosave;
  /** The draft at the canvas's scope, as rendered. */
  view: ScopedDraft;
  /** The newest draft at the canvas's scope (an edit not yet rendered included). */
  latestScoped: () => ScopedDraft;
  /** A change of the scoped draft (one undo step), saved. */
  edit: (change: (d: Draft) => Draft, group?: string) => void;
  editOrders: EditOrders;
  /** The orders the panels show (the mission's, or the team member's) and their edit. */
  panelOrders: Orders;
  editPanelOrders: EditOrders;
  doUndo: () => void;
  doRedo: () => void;
}

export function useEditing(mission: MissionDetail, opening: Promise<Report | null> | null): Editing {
  const store = useEditorApi();
  const client = useQueryClient();
  const drafts = useDraftHistory();
  const { latest, updateHistory } = drafts;
  const view = useScopedDraft();
  const member = useEditor((s) => s.scope.member);
  // Their draft, reloaded after a conflict, is what the page shows from now on.
  const reloaded = useCallback((theirs: MissionDetail) => void draftSaved(client, theirs), [client]);
  const autosave = useAutosave(mission, reloaded, useServerCheck(opening));
  const { edit: editWhole, editOrders: editWholeOrders, changed } = autosave;
  const latestScoped = useCallback(() => scopedDraft(latest(), store.getState().scope), [latest, store]);
  const edit = useCallback(
    (change: (d: Draft) => Draft, group?: string) => editWhole((d) => applyScoped(d, store.getState().scope, change), group),
    [editWhole, store],
  );
  const editOrders = useCallback<EditOrders>((change, group) => edit((d) => ({ ...d, orders: change(d.orders) }), group), [edit]);
  const whole = drafts.history.present.orders;
  const panelOrders = useMemo(() => ordersAt(whole, { member, path: [] }) ?? whole, [whole, member]);
  const editPanelOrders = useCallback<EditOrders>(
    (change, group) => editWholeOrders((o) => applyAtMember(o, store.getState().scope, change), group),
    [editWholeOrders, store],
  );
  const doUndo = useCallback(() => {
    updateHistory(undo);
    changed();
  }, [updateHistory, changed]);
  const doRedo = useCallback(() => {
    updateHistory(redo);
    changed();
  }, [updateHistory, changed]);
  return { ...drafts, autosave, view, latestScoped, edit, editOrders, panelOrders, editPanelOrders, doUndo, doRedo };
}
