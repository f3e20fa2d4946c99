/**
 * The mission editor's state in one store (zustand, as React Flow's state-management guide
 * shows): the draft under undo/redo, the save and conflict state, the server's report and the
 * canvas's nodes and edges. One store per mounted editor (a context gives it to the hooks), so
 * two editors never share a draft. Actions read the newest state with `get()`, so an edit can be
 * sent to the server from its event handler before React renders it.
 */
import { applyEdgeChanges, applyNodeChanges, type Edge, type EdgeChange, type Node, type NodeChange } from "@xyflow/react";
import { createContext, useContext } from "react";
import { createStore, type StoreApi, useStore } from "zustand";

import type { MissionDetail, Report } from "../api/client";
import type { Conflict } from "./ConflictDialog";
import type { Layout, Orders, PathLike } from "./graph";
import { goals, terminals } from "./graph";
import { createHistory, type History } from "./history";
import { layeredLayout } from "./layout";
import type { NodeData } from "./nodes";
import type { Refusal } from "./refusal";
import { openingScope, type Scope } from "./scope";

export interface Draft {
  orders: Orders;
  layout: Layout;
}

export type SaveState = "saved" | "pending" | "saving" | "conflict" | "error";

export interface Highlight {
  path: PathLike;
  label: string;
}

type Update<T> = T | ((previous: T) => T);
function apply<T>(update: Update<T>, previous: T): T {
  return typeof update === "function" ? (update as (p: T) => T)(previous) : update;
}

export interface EditorState {
  missionId: string;
  /** The draft (orders and layout) under undo/redo. */
  history: History<Draft>;
  /** The ETag the next save sends (the revision last read or saved). */
  revision: number;
  /** The orders of that revision: the common ancestor of a three-way merge (merge.ts). */
  base: Orders;
  /** The positions last saved or loaded (saved apart from the orders: no revision). */
  savedLayout: Layout;
  /** The revision last saved or loaded, as rendered (the plain orders re-read on change). */
  savedRevision: number;
  saveState: SaveState;
  saveError: unknown;
  conflict: Conflict | null;
  notice: string;
  /** Spoken by the canvas's live region (connections, copy, paste). */
  connectMessage: string;
  // The server check.
  report: Report | null;
  checkMs: number | null;
  /** The orders whose report is shown; a save of the same orders sends no check. */
  lastChecked: Orders | null;
  /** performance.now() of the last edit (the check time is measured from it). */
  editedAt: number;
  // The canvas.
  nodes: Node<NodeData>[];
  edges: Edge[];
  highlight: Highlight | null;
  /** Whether the canvas shows the newest positions (tests wait for it). */
  ready: boolean;
  /** Whether the opened draft has positions (until then the canvas gets no nodes). */
  placed: boolean;
  panel: string;
  /** The constraint whose scope clicks on goals now toggle ("Pick scope on the graph"), or null. */
  scopePick: string | null;
  /** The last change the server refused (shown beside its field and in Findings), or null. */
  refusal: Refusal | null;
  /** The goal whose neighbourhood is in focus (the rest fades), or null. */
  focus: string | null;
  /** The part of the orders the canvas shows: a team member, a refinement (scope.ts). */
  scope: Scope;

  setHistory: (update: Update<History<Draft>>) => void;
  setNodes: (update: Update<Node<NodeData>[]>) => void;
  setEdges: (update: Update<Edge[]>) => void;
  onNodesChange: (changes: NodeChange<Node<NodeData>>[]) => void;
  onEdgesChange: (changes: EdgeChange[]) => void;
  select: (ids: string[]) => void;

  // Named actions: each says what happened and changes only what that event changes (no
  // generic patch, so every change of the editor's state can be found by its name).
  /** Spoken by the canvas's live region. */
  announce: (message: string) => void;
  /** Whether the canvas shows the newest positions (false while a layout is on its way). */
  showReady: (ready: boolean) => void;
  showPanel: (panel: string) => void;
  /** The opened draft has positions now (or will not get any: default positions are shown). */
  markPlaced: () => void;
  showHighlight: (highlight: Highlight | null) => void;
  focusGoal: (id: string | null) => void;
  pickScopeFor: (constraint: string | null) => void;
  /** The canvas moves to another part of the orders: highlight and focus belong to the old one. */
  openScope: (scope: Scope) => void;
  /** The part shown is replaced (an import, a part an edit removed), nothing else changes. */
  replaceScope: (scope: Scope) => void;
  showNotice: (notice: string) => void;
  /** A request failed outside saving (a layout, the plain orders, the first report). */
  failed: (error: unknown) => void;
  // Autosave (useAutosave.ts).
  edited: () => void;
  savePending: () => void;
  saveStarted: () => void;
  ordersSaved: (revision: number, orders: Orders) => void;
  layoutSaved: (layout: Layout) => void;
  saveFinished: (newestSaved: boolean) => void;
  saveRefused: (error: unknown, refusal: Refusal | null) => void;
  conflictFound: (conflict: Conflict) => void;
  /** Their revision taken under a merged draft (which the next save sends). */
  mergedOnto: (revision: number, base: Orders) => void;
  /** Their draft replaces mine: the saved and checked state is theirs. */
  theirsReloaded: (theirs: MissionDetail) => void;
  // The server's check (useServerCheck.ts).
  showReport: (report: Report) => void;
  /** The report of `orders`, still the newest; `checkMs` from the edit that asked for it. */
  checked: (orders: Orders, report: Report, checkMs: number | null) => void;
}

function openedDraft(mission: MissionDetail): Draft {
  const opened = { orders: mission.orders, layout: mission.layout };
  // A draft without positions is laid out at once (the layered layout is linear time), so that
  // the canvas never renders it unplaced and opening waits for nothing.
  if (goals(opened.orders).length > 0 && !isLaidOut(opened)) {
    opened.layout = { ...layeredLayout(opened.orders, openingAspect()), ...opened.layout };
  }
  return opened;
}

/** The canvas's aspect ratio before it exists (canvas.tsx): the window's width less the page's
 * margins and the side column (30%), its height less the toolbar. */
function openingAspect(): number {
  return Math.min(3, Math.max(0.8, (window.innerWidth * 0.7 - 100) / Math.max(300, window.innerHeight - 120)));
}

/** Whether every goal and terminal of the draft has a position (an empty draft counts as not). */
export function isLaidOut(draft: Draft): boolean {
  const ids = [...goals(draft.orders).map((g) => g.id), ...terminals(draft.orders).map((t) => t.id)];
  return ids.length > 0 && ids.every((id) => draft.layout[id]);
}

/** `report`: the saved draft's report when it came beside the mission (api/reportPrefetch.ts). */
// Length: the store's state and its named actions, one line each, listed together.
export function createEditorStore(mission: MissionDetail, report: Report | null = null): StoreApi<EditorState> {
  performance.mark("editor:first-render");
  const draft = openedDraft(mission);
  return createStore<EditorState>()((set) => ({
    missionId: mission.id,
    history: createHistory(draft),
    revision: mission.revision,
    base: mission.orders,
    savedLayout: mission.layout,
    savedRevision: mission.revision,
    saveState: "saved",
    saveError: null,
    conflict: null,
    notice: "",
    connectMessage: "",
    report,
    checkMs: null,
    lastChecked: mission.orders,
    editedAt: 0,
    nodes: [],
    edges: [],
    highlight: null,
    ready: false,
    placed: isLaidOut(draft),
    panel: "editor-constraints",
    scopePick: null,
    refusal: null,
    focus: null,
    scope: openingScope(mission.orders),

    setHistory: (update) => set((s) => ({ history: apply(update, s.history) })),
    setNodes: (update) => set((s) => ({ nodes: apply(update, s.nodes) })),
    setEdges: (update) => set((s) => ({ edges: apply(update, s.edges) })),
    // Removals go through the orders (deleteSelected), never straight to the canvas.
    onNodesChange: (changes) => set((s) => ({ nodes: applyNodeChanges(changes.filter((c) => c.type !== "remove"), s.nodes) })),
    onEdgesChange: (changes) => set((s) => ({ edges: applyEdgeChanges(changes.filter((c) => c.type !== "remove"), s.edges) })),
    select: (ids) =>
      set((s) => ({
        nodes: s.nodes.map((n) => ({ ...n, selected: ids.includes(n.id) })),
        edges: s.edges.map((e) => ({ ...e, selected: false })),
      })),

    announce: (connectMessage) => set({ connectMessage }),
    showReady: (ready) => set({ ready }),
    showPanel: (panel) => set({ panel }),
    markPlaced: () => set({ placed: true }),
    showHighlight: (highlight) => set({ highlight }),
    focusGoal: (focus) => set({ focus }),
    pickScopeFor: (scopePick) => set({ scopePick }),
    openScope: (scope) => set({ scope, highlight: null, focus: null }),
    replaceScope: (scope) => set({ scope }),
    showNotice: (notice) => set({ notice }),
    failed: (saveError) => set({ saveError }),

    edited: () => set({ editedAt: performance.now() }),
    savePending: () => set({ saveState: "pending" }),
    saveStarted: () => set({ saveState: "saving" }),
    ordersSaved: (revision, orders) => set({ revision, savedRevision: revision, base: orders, saveError: null }),
    layoutSaved: (savedLayout) => set({ savedLayout }),
    saveFinished: (newestSaved) => set({ saveError: null, refusal: null, saveState: newestSaved ? "saved" : "pending" }),
    // A refused change is shown beside its field, on the panel (or goal) that holds it.
    saveRefused: (saveError, refusal) =>
      set({ saveError, saveState: "error", refusal, ...(refusal?.panel ? { panel: refusal.panel } : {}) }),
    conflictFound: (conflict) => set({ conflict, saveState: "conflict" }),
    mergedOnto: (revision, base) => set({ revision, base, conflict: null, saveState: "pending" }),
    theirsReloaded: (theirs) =>
      set({
        revision: theirs.revision,
        savedRevision: theirs.revision,
        lastChecked: theirs.orders,
        base: theirs.orders,
        savedLayout: theirs.layout,
        conflict: null,
        saveState: "saved",
        notice: "Reloaded the draft someone else saved.",
      }),

    showReport: (report) => set({ report }),
    checked: (orders, report, checkMs) =>
      set({ lastChecked: orders, report, ...(checkMs !== null ? { checkMs } : {}) }),
  }));
}

export const EditorStoreContext = createContext<StoreApi<EditorState> | null>(null);

/** The editor's store (for actions that read the newest state with getState()). */
export function useEditorApi(): StoreApi<EditorState> {
  const store = useContext(EditorStoreContext);
  if (!store) throw new Error("useEditorApi outside the mission editor");
  return store;
}

/** A slice of the editor's state; the component re-renders when that slice changes. */
export function useEditor<T>(selector: (state: EditorState) => T): T {
  return useStore(useEditorApi(), selector);
}
