/** Every action of the editor, composed from the hooks that own them, as one object that the
 * toolbar, the canvas's keys and the panels share. */
import { type RefObject, useMemo, useState } from "react";

import type { MissionDetail, Report } from "../api/client";
import { goals } from "./graph";
import { type Clipboard, useClipboard } from "./useClipboard";
import { type Editing, useEditing } from "./useEditing";
import { useImport } from "./useImport";
import { type NodeActions, useNodeActions } from "./useNodeActions";
import { type OpenView, useOpenView } from "./useOpenView";
import { type ScopeNavigation, useScopeNavigation } from "./useScopeNavigation";
import { useSelectWhenShown } from "./useSelectWhenShown";
import { useViewMoves, type ViewMoves } from "./useViewMoves";

export interface Dialogs {
  shortcuts: boolean;
  plan: boolean;
  showShortcuts: (open: boolean) => void;
  showPlan: (open: boolean) => void;
}

export interface EditorActions extends NodeActions, Clipboard, ViewMoves, ScopeNavigation {
  doUndo: () => void;
  doRedo: () => void;
  importFile: (file: File) => Promise<void>;
  importing: boolean;
  dialogs: Dialogs;
}

export interface EditorParts {
  editing: Editing;
  open: OpenView;
  actions: EditorActions;
}

export function useEditorActions(mission: MissionDetail, opening: Promise<Report | null> | null, titleRef: RefObject<HTMLInputElement | null>): EditorParts {
  const editing = useEditing(mission, opening);
  const [openedGoals] = useState(() => goals(mission.orders).length);
  const open = useOpenView(editing, openedGoals);
  const selectWhenShown = useSelectWhenShown();
  const nodeActions = useNodeActions(editing, open, selectWhenShown, titleRef);
  const clipboard = useClipboard(editing, selectWhenShown);
  const moves = useViewMoves(editing);
  const scopes = useScopeNavigation(open.showLaidOutThenReady);
  const { importFile, importing } = useImport(mission.id, editing, open.fitWhenPlaced);
  const [shortcuts, showShortcuts] = useState(false);
  const [plan, showPlan] = useState(false);
  const { doUndo, doRedo } = editing;
  const actions = useMemo<EditorActions>(
    () => ({ ...nodeActions, ...clipboard, ...moves, ...scopes, doUndo, doRedo, importFile, importing, dialogs: { shortcuts, plan, showShortcuts, showPlan } }),
    [nodeActions, clipboard, moves, scopes, doUndo, doRedo, importFile, importing, shortcuts, plan],
  );
  return { editing, open, actions };
}
