/**
 * The graph editor of a mission draft (operators). The pure logic lives in graph.ts,
 * history.ts and layout.ts; the state in one store (store.ts) with hooks for the draft's
 * history, autosave and conflict, the server check and the canvas's elements. Every edit sends
 * the new orders to /api/validate at once (from the event handler, before React renders the
 * edit), then saves the draft with If-Match; typing waits for a pause first. The plain orders
 * are fetched only while their tab is open.
 */
import "@xyflow/react/dist/style.css";
import "./editor.css";

import { Background, type Connection, Controls, type Edge, type FinalConnectionState, type Node, ReactFlow, ReactFlowProvider, useReactFlow } from "@xyflow/react";
import { type KeyboardEvent, useCallback, useEffect, useMemo, useRef, useState } from "react";

import { exportHref, fetchText, type Finding, type MissionDetail, type Report } from "../api/client";
import { type ReportPrefetch, reportOf } from "../api/reportPrefetch";
import { ErrorMessage } from "../components/Status";
import { plural } from "../format";
import {
  addGoal,
  addTerminal,
  checkConnection,
  connect,
  deleteNodes,
  disconnect,
  findingPath,
  goals,
  type Orders,
  OUTCOME_LETTER,
  type Outcome,
  type PathLike,
  terminals,
  updateTerminal,
} from "./graph";
import { knownQuantities } from "./expr";
import { canRedo, canUndo, redo, reset, undo } from "./history";
import { copyGoals, pasteGoals, patch, readClip } from "./model";
import { AreasPanel, MissionPanel, NormsPanel, QuantitiesPanel, VehiclePanel } from "./panels";
import { PathsPanel } from "./PathsPanel";
import { ImportMenu, NewFromExample, readOrdersFile } from "./ImportMenu";
import { PlanDialog } from "./PlanDialog";
import { Tabs } from "../components/Tabs";
import { canvasAspect, layoutOffThread } from "./layoutClient";
import { GOAL_SIZE } from "./layout";
import { EDGE_TYPES, NODE_TYPES } from "./nodes";
import { ConflictDialog } from "./ConflictDialog";
import { createEditorStore, EditorStoreContext, isLaidOut, useEditor, useEditorApi } from "./store";
import { useDraftHistory } from "./useDraftHistory";
import { useServerCheck } from "./useServerCheck";
import { useAutosave } from "./useAutosave";
import { LARGE_GOALS, useFlowElements } from "./useFlowElements";
import { ConstraintsPanel, FindingsList, GoalInspector, useScopePickClick } from "./Inspector";
import { CommitSelect } from "./fields";
import { ExportMenu, ToolbarMenu } from "./Toolbar";
import { readyWhenShown, showLaidOut } from "./ready";
import { FIT, freePlace, GOTO_ZOOM, MIN_ZOOM, trackConnectPointer, SideMinimap, Splitter, useEditorFrame, useSideWidth, ZoomDetail } from "./canvas";
import { ShortcutsDialog } from "./Shortcuts";
import { RefusedNote } from "./RefusedNote";
import { addRefinement, crumbsOf, defaultReturn, isOutcome, openingScope, ordersAt, removeRefinement, type Scope, setReturns, teamOf, TOP } from "./scope";
import { applyAtMember, applyScoped, scopedDraft, useScopedDraft } from "./useScopedDraft";
import type { Draft } from "./store";

const PANELS = [
  { id: "editor-constraints", label: "Constraints" },
  { id: "editor-norms", label: "Norms" },
  { id: "editor-areas", label: "Areas" },
  { id: "editor-quantities", label: "Quantities" },
  { id: "editor-vehicle", label: "Vehicle" },
  { id: "editor-mission", label: "Mission" },
  { id: "editor-paths", label: "Path explorer" },
  { id: "editor-plain", label: "Plain orders" },
];
const CLIP_KEY = "countersign.editor.clipboard";

/** Who else meets at a meeting: "Meets vehicle-2 at G2 (Rendezvous ...)", or that nobody does. */
function partnersText(team: { vehicle: string; orders: Orders }[], member: number | null, meet: string): string {
  const others = team.flatMap((m, i) =>
    i === member ? [] : goals(m.orders).filter((g) => g.meet === meet).map((g) => `${m.vehicle} at ${g.id}${g.title ? ` (${g.title})` : ""}`),
  );
  return others.length > 0 ? `Meets ${others.join(" and ")}.` : `No other vehicle names meeting ${meet}: nobody will come (TEAM).`;
}

/** `onSaved` gets the mission as the save answered it (the page shows it without re-reading).
 * `report`: the saved draft's report if the page asked for it beside the mission; it is used only
 * if it is of this draft (its digest), else the editor asks for it. */
export default function MissionEditor(props: { mission: MissionDetail; report?: ReportPrefetch | null; onSaved: (saved: MissionDetail) => void }) {
  const { mission, report, onSaved } = props;
  const [store] = useState(() => createEditorStore(mission, reportOf(report, mission.draft_digest)));
  const [opening] = useState(() => report?.done.then(() => reportOf(report, mission.draft_digest)) ?? null);
  return (
    <EditorStoreContext.Provider value={store}>
      <ReactFlowProvider>
        <Editor mission={mission} onSaved={onSaved} opening={opening} />
      </ReactFlowProvider>
    </EditorStoreContext.Provider>
  );
}

function Editor({ mission, onSaved, opening }: { mission: MissionDetail; onSaved: (saved: MissionDetail) => void; opening: Promise<Report | null> | null }) {
  const flow = useReactFlow();
  const store = useEditorApi();
  const { history, latest: latestWhole, updateHistory } = useDraftHistory();
  const draft = history.present;
  // The canvas shows the part of the orders in scope (a team member, a refinement: scope.ts).
  const scope = useEditor((s) => s.scope);
  const view = useScopedDraft();
  const orders = view.orders;
  const latest = useCallback(() => scopedDraft(latestWhole(), store.getState().scope), [latestWhole, store]);
  const { markPlaced, showHighlight, failed, focusGoal, openScope: enterScope, replaceScope, showNotice } = store.getState();
  const savedRevision = useEditor((s) => s.savedRevision);
  const revision = useEditor((s) => s.revision);
  const saveState = useEditor((s) => s.saveState);
  const saveError = useEditor((s) => s.saveError);
  const conflict = useEditor((s) => s.conflict);
  const notice = useEditor((s) => s.notice);
  const connectMessage = useEditor((s) => s.connectMessage);
  const report = useEditor((s) => s.report);
  const checkMs = useEditor((s) => s.checkMs);
  const highlight = useEditor((s) => s.highlight);
  const ready = useEditor((s) => s.ready);
  const panel = useEditor((s) => s.panel);
  const nodes = useEditor((s) => s.nodes);
  const edges = useEditor((s) => s.edges);
  const onNodesChange = useEditor((s) => s.onNodesChange);
  const onEdgesChange = useEditor((s) => s.onEdgesChange);
  const select = useEditor((s) => s.select);
  const refusal = useEditor((s) => s.refusal);
  const focus = useEditor((s) => s.focus);
  const [shortcutsOpen, setShortcutsOpen] = useState(false);
  const setConnectMessage = useEditor((s) => s.announce);
  const setReady = useEditor((s) => s.showReady);
  const setPanel = useEditor((s) => s.showPanel);
  const [plain, setPlain] = useState<string>("");

  useEffect(() => {
    performance.mark("editor:mounted");
  }, []);

  const server = useServerCheck(opening);
  const autosave = useAutosave(mission, onSaved, server);
  const { changed, saveComputedLayout, reloadTheirs, resolve } = autosave;
  const editWhole = autosave.edit;
  // Edits of the canvas apply to the part in scope; the whole draft is saved.
  const edit = useCallback(
    (change: (d: Draft) => Draft, group?: string) => editWhole((d) => applyScoped(d, store.getState().scope, change), group),
    [editWhole, store],
  );
  const editOrders = useCallback(
    (change: (o: Orders) => Orders, group?: string) => edit((d) => ({ ...d, orders: change(d.orders) }), group),
    [edit],
  );
  // The panels (constraints, areas, vehicle...) edit the orders of the mission or team member.
  const panelOrders = useMemo(() => ordersAt(draft.orders, { member: scope.member, path: [] }) ?? draft.orders, [draft.orders, scope.member]);
  const editPanelOrders = useCallback(
    (change: (o: Orders) => Orders, group?: string) => autosave.editOrders((o) => applyAtMember(o, store.getState().scope, change), group),
    [autosave, store],
  );
  const onScopePickClick = useScopePickClick(editPanelOrders);

  // Lay out a draft that has no positions yet (new or imported), without an undo step.
  // Small orders open fitted to the canvas; large ones open at the start goal at a readable
  // zoom, so that only the nodes in view are rendered (the toolbar's "Zoom to fit" shows all).
  const laidOut = useRef(false);
  const large = useRef(goals(mission.orders).length > LARGE_GOALS);
  const openView = useRef(false);
  useEffect(() => {
    if (ready) performance.mark("editor:ready");
  }, [ready]);
  useEffect(() => {
    if (laidOut.current) return;
    laidOut.current = true;
    if (isLaidOut(draft)) {
      openView.current = true;
      saveComputedLayout(draft.layout); // a large draft laid out as it opened (store.ts)
      return;
    }
    void layoutOffThread(orders, {}, canvasAspect()).then(
      (layout) => {
        openView.current = true;
        updateHistory((h) => reset({ ...h.present, layout: { ...layout, ...h.present.layout } }));
        markPlaced();
        saveComputedLayout(layout);
      },
      () => {
        openView.current = true;
        markPlaced(); // no layout: show the default positions rather than nothing
      },
    );
  }, [orders, draft, updateHistory, saveComputedLayout, markPlaced]);

  // ---- React Flow nodes and edges, synchronised with the draft ----
  const { graph, findings, local, markers } = useFlowElements(large.current);
  const highlightPath = useCallback((path: PathLike | null, label = "") => showHighlight(path ? { path, label } : null), [showHighlight]);
  const selectNext = useRef<string[] | null>(null);

  // Zoom to fit once the nodes carry their new positions (after an auto layout). A large draft
  // (over LARGE_GOALS) is shown at its start goal at a readable zoom instead, as it opens: a fit
  // would mount every node at once (about 400 ms without a frame for 500 goals) to show text
  // too small to read; "Zoom to fit" still shows all of it.
  const fitPending = useRef(false);
  // "ready" waits for the view to show the new positions (ready.ts).
  const showLaidOutThenReady = useCallback(() => {
    void readyWhenShown(() => showLaidOut(flow, large.current, store.getState().nodes, FIT), setReady);
  }, [flow, store, setReady]);
  useEffect(() => {
    if (openView.current && nodes.length > 0) {
      openView.current = false;
      window.requestAnimationFrame(showLaidOutThenReady);
      return;
    }
    if (!fitPending.current) return;
    fitPending.current = false;
    window.requestAnimationFrame(showLaidOutThenReady);
  }, [nodes, showLaidOutThenReady]);

  // Select what was just added once its node exists (the inspector then shows it).
  useEffect(() => {
    const wanted = selectNext.current;
    if (wanted && wanted.every((id) => nodes.some((n) => n.id === id))) {
      selectNext.current = null;
      select(wanted);
    }
  }, [nodes, select]);

  const [gotoText, setGotoText] = useState("");
  const editorRef = useRef<HTMLDivElement>(null);
  const mainRef = useRef<HTMLDivElement>(null);
  const canvasRef = useRef<HTMLDivElement>(null);
  // The scope bar (team members, breadcrumbs) shows above the canvas for teams and refinements.
  const scopeBar = teamOf(draft.orders) !== null || scope.path.length > 0;
  const frameHeight = useEditorFrame(editorRef, mainRef, scopeBar);
  const [sideWidth, setSideWidth] = useSideWidth();
  // The plain orders (as saved): fetched when their tab opens and after each save while open.
  const plainShown = panel === "editor-plain";
  useEffect(() => {
    if (!plainShown) return;
    let current = true;
    fetchText(exportHref(mission.id, "plain")).then((text) => current && setPlain(text), (e: unknown) => current && failed(e));
    return () => {
      current = false;
    };
  }, [plainShown, savedRevision, mission.id, failed]);
  const [planOpen, setPlanOpen] = useState(false);
  const known = useMemo(() => knownQuantities(panelOrders), [panelOrders]);
  const goTo = (id: string) => {
    const node = graph.nodes.find((n) => n.id === id);
    if (!node) {
      setConnectMessage(`No node ${id}.`);
      return;
    }
    select([id]);
    // At one zoom whatever the zoom was: kept at a new draft's fit (1.2), a 1024 px canvas showed
    // the node's successor mostly under the inspector, and a wire dragged to it auto-panned.
    void flow.setCenter(node.position.x + GOAL_SIZE.width / 2, node.position.y + GOAL_SIZE.height / 2, { zoom: GOTO_ZOOM });
  };

  const selectedNodes = nodes.filter((n) => n.selected).map((n) => n.id);
  const selectedId = selectedNodes.length === 1 ? selectedNodes[0] : undefined;

  const onConnect = useCallback(
    (c: Connection) => {
      const result = connect(latest().orders, c.source, c.sourceHandle ?? "", c.target);
      if (!result.check.ok) {
        setConnectMessage(result.check.reason ?? "That connection is not allowed.");
        return;
      }
      setConnectMessage(`Connected ${c.source} ${c.sourceHandle} to ${c.target}.`);
      // Applied to the newest orders (a previous edit may not have rendered yet).
      editOrders((o) => connect(o, c.source, c.sourceHandle ?? "", c.target).orders);
    },
    [editOrders, latest, setConnectMessage],
  );
  // A connection dropped anywhere on a node's body (not only on its input dot) connects to it.
  const onConnectEnd = useCallback(
    (event: MouseEvent | TouchEvent, state: FinalConnectionState) => {
      if (state.isValid || !state.fromNode || !state.fromHandle?.id || state.fromHandle.type !== "source") return;
      const point = "changedTouches" in event ? event.changedTouches[0] : event;
      if (!point) return;
      // The topmost element under the pointer: a node hidden by the inspector or a menu is not hit.
      const hit = document.elementFromPoint(point.clientX, point.clientY)?.closest(".editor-canvas .react-flow__node");
      const target = hit?.getAttribute("data-id");
      if (!target || target === state.fromNode.id) return;
      onConnect({ source: state.fromNode.id, sourceHandle: state.fromHandle.id, target, targetHandle: "in" });
    },
    [onConnect],
  );
  const [pointer] = useState(() => trackConnectPointer(() => canvasRef.current));
  const isValidConnection = useCallback(
    (c: Connection | Edge) => pointer.inside() && checkConnection(latest().orders, c.source, c.sourceHandle, c.target).ok,
    [latest, pointer],
  );

  const onNodeDragStop = useCallback(
    (_event: unknown, _node: Node, dragged: Node[]) => {
      edit((d) => {
        const layout = { ...d.layout };
        for (const n of dragged) layout[n.id] = { x: Math.round(n.position.x), y: Math.round(n.position.y) };
        return { ...d, layout };
      });
    },
    [edit],
  );

  // New nodes go to free space: beside the selected node, else near the centre of the view.
  const placeNew = useCallback((): { x: number; y: number } => {
    const pane = document.querySelector(".editor-canvas")?.getBoundingClientRect();
    const centre = pane
      ? flow.screenToFlowPosition({ x: pane.left + pane.width / 2, y: pane.top + pane.height / 2 })
      : { x: 0, y: 0 };
    const sizes: Record<string, { width: number; height: number }> = {};
    let selected: { x: number; y: number } | null = null;
    for (const n of store.getState().nodes) {
      if (n.measured?.width && n.measured.height) sizes[n.id] = { width: n.measured.width, height: n.measured.height };
      if (n.selected && !selected) selected = n.position;
    }
    const at = freePlace(latest().layout, sizes, selected, centre);
    // Keep the new node in view (the zoom stays as it is).
    if (pane) {
      const corner = flow.flowToScreenPosition(at);
      const far = flow.flowToScreenPosition({ x: at.x + 220, y: at.y + 112 });
      if (corner.x < pane.left || corner.y < pane.top || far.x > pane.right || far.y > pane.bottom) {
        void flow.setCenter(at.x + 110, at.y + 56, { zoom: flow.getZoom() });
      }
    }
    return at;
  }, [flow, latest, store]);

  const titleRef = useRef<HTMLInputElement>(null);
  const addGoalNode = () => {
    const at = placeNew();
    const { orders: next, id } = addGoal(latest().orders);
    selectNext.current = [id];
    edit((d) => ({ orders: next, layout: { ...d.layout, [id]: at } }));
    window.setTimeout(() => titleRef.current?.select(), 50);
  };
  const addTerminalNode = (kind: "complete" | "abort") => {
    const at = placeNew();
    const added = addTerminal(latest().orders, kind);
    const id = added.id;
    // A refinement's terminal returns one of the parent goal's outcomes.
    const next = view.refinement ? setReturns(added.orders, id, defaultReturn(kind)) : added.orders;
    selectNext.current = [id];
    edit((d) => ({ orders: next, layout: { ...d.layout, [id]: at } }));
  };
  const deleteSelected = () => {
    const { nodes: ns, edges: es } = store.getState();
    const nodeIds = ns.filter((n) => n.selected).map((n) => n.id);
    const edgeList = es.filter((e) => e.selected);
    if (nodeIds.length === 0 && edgeList.length === 0) return;
    edit((d) => {
      let o = deleteNodes(d.orders, nodeIds);
      for (const e of edgeList) o = disconnect(o, e.source, e.sourceHandle as Outcome, e.target);
      const layout = { ...d.layout };
      for (const id of nodeIds) delete layout[id];
      return { orders: o, layout };
    });
  };
  const relayout = async () => {
    setReady(false); // the canvas says when the new positions are shown (tests wait for it)
    const sizes: Record<string, { width: number; height: number }> = {};
    for (const n of flow.getNodes()) {
      if (n.measured?.width && n.measured.height) sizes[n.id] = { width: n.measured.width, height: n.measured.height };
    }
    let layout;
    try {
      layout = await layoutOffThread(latest().orders, sizes, canvasAspect());
    } catch (e) {
      failed(e);
      setReady(true);
      return;
    }
    // A layout equal to the one shown changes no node: fit (and say ready) at once. Otherwise
    // the fit waits for the nodes to carry the new positions (the effect above); a timer that
    // fitted after 150 ms came first on a loaded machine and fitted the old positions.
    const shown = latest().layout;
    if (Object.entries(layout).every(([id, p]) => shown[id]?.x === p.x && shown[id]?.y === p.y)) {
      showLaidOutThenReady();
      return;
    }
    fitPending.current = true;
    edit((d) => ({ ...d, layout }));
  };
  // Import: the server reads the file (nothing stored); the draft is replaced by one ordinary
  // edit (undoable), laid out afresh, and saved with If-Match like any other.
  const [importing, setImporting] = useState(false);
  const importFile = async (file: File) => {
    setImporting(true);
    try {
      const { orders: read, findings: found } = await readOrdersFile(file);
      const next: Orders = { ...read, id: mission.id };
      const layout = await layoutOffThread(next, {}, canvasAspect());
      setReady(false);
      fitPending.current = true;
      replaceScope(openingScope(next));
      editWhole(() => ({ orders: next, layout }));
      const codes = [...new Set(found.map((f) => f.code).filter(Boolean))];
      showNotice(
        `Imported ${file.name}: ${plural(goals(next).length, "goal")}${codes.length > 0 ? `; reading it found ${codes.join(", ")}` : ""}. Undo brings the previous draft back.`,
      );
    } finally {
      setImporting(false);
    }
  };
  const doUndo = () => {
    updateHistory(undo);
    changed();
  };
  const doRedo = () => {
    updateHistory(redo);
    changed();
  };

  // "Focus this goal": its predecessors and successors in view, the rest faded (useFlowElements).
  const focusOn = (id: string | null) => {
    focusGoal(id);
    if (!id) {
      void flow.fitView(FIT);
      return;
    }
    const near = new Set([id]);
    for (const e of edges) {
      if (e.source === id) near.add(e.target);
      if (e.target === id) near.add(e.source);
    }
    void flow.fitView({ nodes: [...near].map((n) => ({ id: n })), padding: 0.25, maxZoom: 1, minZoom: MIN_ZOOM });
  };
  // ---- Scope: a team member's canvas, a refinement's canvas (scope.ts) ----
  const team = teamOf(draft.orders);
  const crumbs = crumbsOf(draft.orders, scope);
  const openScope = (next: Scope) => {
    if (next.member === scope.member && next.path.join("/") === scope.path.join("/")) return;
    setReady(false);
    enterScope(next);
    setConnectMessage(next.path.length > 0 ? `Showing the refinement of ${next.path[next.path.length - 1]}.` : "Showing the mission.");
    // Fitted once the canvas carries the nodes of the new scope.
    window.requestAnimationFrame(() => window.requestAnimationFrame(showLaidOutThenReady));
  };
  const openRefinement = (id: string) => openScope({ member: scope.member, path: [...scope.path, id] });
  // A scope that an edit (undo, someone else's save) removed falls back to the member or mission.
  useEffect(() => {
    if (ordersAt(draft.orders, scope)) return;
    const member = { member: scope.member, path: [] };
    replaceScope(ordersAt(draft.orders, member) && scope.member !== null ? member : team ? openingScope(draft.orders) : TOP);
  }, [draft.orders, scope, replaceScope, team]);

  // A refused change of a goal's or terminal's field: select it, so that its inspector shows
  // the field with the refusal beside it.
  useEffect(() => {
    if (refusal?.select) select([refusal.select]);
  }, [refusal, select]);

  // Shortcuts act only while focus is in the canvas (not in the inspector's fields).
  const onCanvasKey = (event: KeyboardEvent<HTMLDivElement>) => {
    const target = event.target as HTMLElement;
    if (target.closest("input, textarea, select")) return;
    const mod = event.ctrlKey || event.metaKey;
    const key = event.key.toLowerCase();
    if (mod && key === "z" && !event.shiftKey) doUndo();
    else if (mod && (key === "y" || (key === "z" && event.shiftKey))) doRedo();
    else if (event.key === "Delete" || event.key === "Backspace") deleteSelected();
    else if (mod && key === "c") copySelected();
    else if (mod && key === "v") pasteSelected();
    else if (mod && key === "d") duplicateSelected();
    else if (!mod && key === "g" && !event.altKey) addGoalNode();
    else if (!mod && key === "l" && !event.altKey) void relayout();
    else if (!mod && key === "f" && !event.altKey && selectedId) focusOn(selectedId);
    else if (!mod && key === "o" && !event.altKey && selectedGoal?.refines) openRefinement(selectedGoal.id);
    else if (!mod && key === "u" && !event.altKey && scope.path.length > 0) openScope({ member: scope.member, path: scope.path.slice(0, -1) });
    else if (event.key === "Escape" && focus) focusOn(null);
    else if (event.key === "?") setShortcutsOpen(true);
    else return;
    event.preventDefault();
  };

  // ---- Copy, paste, duplicate (clipboard JSON; also kept in localStorage between missions) ----
  const copySelected = () => {
    const clip = copyGoals(latest().orders, latest().layout, selectedNodes);
    if (!clip) {
      setConnectMessage("Select goals to copy.");
      return null;
    }
    const text = JSON.stringify(clip);
    try {
      window.localStorage.setItem(CLIP_KEY, text);
    } catch {
      /* storage full or disabled: the system clipboard may still work */
    }
    void navigator.clipboard?.writeText(text).catch(() => undefined);
    setConnectMessage(`Copied ${plural(clip.goals.length, "goal")}.`);
    return clip;
  };
  const pasteClip = (text: string | null) => {
    const clip = readClip(text);
    if (!clip) {
      setConnectMessage("Nothing to paste: copy goals first.");
      return;
    }
    const result = pasteGoals(latest().orders, latest().layout, clip);
    selectNext.current = result.ids;
    edit(() => ({ orders: result.orders, layout: result.layout }));
    setConnectMessage(`Pasted ${result.ids.join(", ")}.`);
  };
  const pasteSelected = () => {
    let text: string | null = null;
    try {
      text = window.localStorage.getItem(CLIP_KEY);
    } catch {
      text = null;
    }
    if (text) pasteClip(text);
    else void navigator.clipboard?.readText().then(pasteClip, () => pasteClip(null));
  };
  const duplicateSelected = () => {
    const clip = copyGoals(latest().orders, latest().layout, selectedNodes);
    if (clip) pasteClip(JSON.stringify(clip));
  };

  const nodeIds = useRef(new Set<string>());
  nodeIds.current = new Set(graph.nodes.map((n) => n.id));
  const pickFinding = useCallback(
    (f: Finding, given: string[] = f.subjects) => {
      const prefix = scopedDraft(latestWhole(), store.getState().scope).prefix;
      const subjects = prefix === "" ? given : given.filter((s) => s.startsWith(prefix)).map((s) => s.slice(prefix.length).split("/")[0]!);
      select(subjects);
      const shown = subjects.filter((id) => nodeIds.current.has(id));
      if (shown.length > 0) void flow.fitView({ nodes: shown.map((id) => ({ id })), padding: 0.5, maxZoom: 1 });
      const path = findingPath(f);
      highlightPath(path, path ? `${f.code} counterexample` : "");
    },
    [select, flow, highlightPath, latestWhole, store],
  );
  const nodeOptions = useMemo(
    () =>
      graph.nodes.map((n) => (
        <option key={n.id} value={n.id}>
          {n.label}
        </option>
      )),
    [graph.nodes],
  );

  const selectedGoal = goals(orders).find((g) => g.id === selectedId);
  const selectedTerminal = terminals(orders).find((t) => t.id === selectedId);
  const errors = findings.filter((f) => f.severity === "error").length;
  return (
    <div className="editor" ref={editorRef}>
      <div className="editor-toolbar" role="toolbar" aria-label="Graph editing" data-testid="editor-toolbar">
        {/* One row at 1280 px: the less frequent actions sit in menus (details/summary: Tab
            reaches each summary, Enter or Space opens it, Escape closes it). */}
        <button type="button" onClick={addGoalNode}>
          Add goal
        </button>
        <ToolbarMenu label="Add terminal">
          <button type="button" className="menu-item" onClick={() => addTerminalNode("complete")}>
            Add complete terminal
          </button>
          <button type="button" className="menu-item" onClick={() => addTerminalNode("abort")}>
            Add abort terminal
          </button>
        </ToolbarMenu>
        <ToolbarMenu label="Edit">
          <button type="button" className="menu-item" onClick={deleteSelected} disabled={selectedNodes.length === 0 && !edges.some((e) => e.selected)}>
            Delete selected
          </button>
          <button type="button" className="menu-item" onClick={duplicateSelected} disabled={!selectedNodes.some((id) => goals(orders).some((g) => g.id === id))}>
            Duplicate
          </button>
          <button type="button" className="menu-item" onClick={() => copySelected()} disabled={selectedNodes.length === 0}>
            Copy
          </button>
          <button type="button" className="menu-item" onClick={pasteSelected}>
            Paste
          </button>
        </ToolbarMenu>
        <button type="button" onClick={doUndo} disabled={!canUndo(history)}>
          Undo
        </button>
        <button type="button" onClick={doRedo} disabled={!canRedo(history)}>
          Redo
        </button>
        <button type="button" onClick={() => void relayout()}>
          Auto layout
        </button>
        <form
          className="goto"
          onSubmit={(e) => {
            e.preventDefault();
            goTo(gotoText.trim());
          }}
        >
          <label htmlFor="goto-node">Go to node</label>
          <input id="goto-node" list="node-ids" size={6} value={gotoText} onChange={(e) => setGotoText(e.target.value)} />
          <datalist id="node-ids">{nodeOptions}</datalist>
          <button type="submit">Go</button>
        </form>
        <ToolbarMenu label="More">
          <button type="button" className="menu-item" onClick={() => void flow.fitView(FIT)}>
            Zoom to fit
          </button>
          <button type="button" className="menu-item" onClick={() => setPlanOpen(true)}>
            Plan survey…
          </button>
          <ImportMenu onImport={importFile} busy={importing} />
          <ExportMenu missionId={mission.id} saved={saveState === "saved"} />
          <NewFromExample />
        </ToolbarMenu>
        <button type="button" onClick={() => setShortcutsOpen(true)} aria-haspopup="dialog" data-testid="shortcuts-button" title="Keyboard shortcuts (?)">
          ?<span className="visually-hidden"> Keyboard shortcuts</span>
        </button>
        <span className={`save-state save-${saveState}`} role="status" data-testid="save-state">
          {saveState === "saved" ? "Saved" : saveState === "pending" || saveState === "saving" ? "Saving…" : saveState === "conflict" ? "Conflict" : "Not saved"}
        </span>
      </div>
      <ErrorMessage error={saveError} />
      {notice && (
        <p className="message" data-testid="editor-notice">
          {notice}
        </p>
      )}
      <p className="visually-hidden" aria-live="polite">
        {connectMessage}
      </p>
      {highlight && (
        <p className="message" data-testid="highlight-note">
          Highlighted on the graph (thick edges marked ●): {highlight.label || "path"}{" "}
          <code>
            {highlight.path.goals.map((g, i) => `${g} ${OUTCOME_LETTER[highlight.path.outcomes[i] as Outcome] ?? "?"}`).join(" → ")}
            {highlight.path.terminal ? ` → ${highlight.path.terminal}` : ""}
          </code>{" "}
          <button type="button" onClick={() => showHighlight(null)}>
            Clear highlight
          </button>
        </p>
      )}
      {scopeBar && (
        <div className="editor-scope" data-testid="editor-scope">
          {team && (
            <div className="members" role="group" aria-label="Team member shown on the canvas">
              <span>Vehicle:</span>
              {team.map((m, i) => (
                <button type="button" key={`${i}-${m.vehicle}`} aria-pressed={scope.member === i} onClick={() => openScope({ member: i, path: [] })} data-testid={`member-${m.vehicle}`}>
                  {m.vehicle}
                </button>
              ))}
            </div>
          )}
          {scope.path.length > 0 && (
            <nav aria-label="Refinement breadcrumbs" data-testid="breadcrumbs">
              <ol>
                {crumbs.map((c, i) =>
                  i === crumbs.length - 1 ? (
                    <li key={i}>
                      <span aria-current="location" data-testid="crumb-current">
                        {c.label}
                      </span>
                    </li>
                  ) : (
                    <li key={i}>
                      <button type="button" className="link-button" onClick={() => openScope(c.scope)} data-testid={`crumb-${i}`}>
                        {c.label}
                      </button>
                    </li>
                  ),
                )}
              </ol>
            </nav>
          )}
        </div>
      )}
      <div className="editor-main" ref={mainRef} style={{ height: frameHeight, gridTemplateColumns: `minmax(0, 1fr) 8px ${sideWidth}px` }}>
        <div
          ref={canvasRef}
          className="editor-canvas"
          tabIndex={0}
          role="group"
          aria-label="Mission graph (Tab moves between nodes; press ? for the keyboard shortcuts)"
          onKeyDown={onCanvasKey}
          data-testid="editor-canvas"
          data-ready={ready ? "true" : "false"}
        >
          <ReactFlow
            nodes={nodes}
            edges={edges}
            nodeTypes={NODE_TYPES}
            edgeTypes={EDGE_TYPES}
            onNodesChange={onNodesChange}
            onEdgesChange={onEdgesChange}
            onConnect={onConnect}
            onConnectStart={pointer.start}
            onConnectEnd={onConnectEnd}
            isValidConnection={isValidConnection}
            onNodeDragStop={onNodeDragStop}
            // A constraint's scope names the goals of the mission (or member), not of a refinement.
            onNodeClick={view.refinement ? undefined : onScopePickClick}
            onNodeDoubleClick={(_e, node) => {
              if (goals(latest().orders).find((g) => g.id === node.id)?.refines) openRefinement(node.id);
            }}
            deleteKeyCode={null}
            edgesFocusable={false}
            minZoom={MIN_ZOOM}
            fitView={!large.current}
            fitViewOptions={FIT}
            onlyRenderVisibleElements={nodes.length > LARGE_GOALS}
            proOptions={{ hideAttribution: true }}
          >
            <Background />
            <Controls showInteractive={false} fitViewOptions={FIT} />
            <ZoomDetail canvas={canvasRef} />
          </ReactFlow>
        </div>
        <Splitter width={sideWidth} onWidth={setSideWidth} />
        <aside className="editor-side" aria-label="Inspector and findings">
          <SideMinimap width={sideWidth - 8} height={Math.round(Math.min(140, Math.max(80, frameHeight * 0.16)))} />
          <section className="editor-inspector" aria-labelledby="editor-inspector-title" tabIndex={0} data-testid="editor-inspector">
          <h3 id="editor-inspector-title">Inspector</h3>
          {selectedGoal && (
            <p className="focus-row">
              {focus === selectedGoal.id ? (
                <button type="button" onClick={() => focusOn(null)} data-testid="unfocus-goal">
                  Show the whole graph
                </button>
              ) : (
                <button type="button" onClick={() => focusOn(selectedGoal.id)} data-testid="focus-goal">
                  Focus this goal (F)
                </button>
              )}
            </p>
          )}
          {selectedGoal && (
            <p className="focus-row" data-testid="refinement-row">
              {selectedGoal.refines ? (
                <>
                  <button type="button" onClick={() => openRefinement(selectedGoal.id)} data-testid="open-refinement">
                    Open refinement
                  </button>{" "}
                  <button type="button" onClick={() => editOrders((o) => removeRefinement(o, selectedGoal.id))} data-testid="remove-refinement">
                    Remove refinement
                  </button>
                </>
              ) : (
                <button type="button" onClick={() => editOrders((o) => addRefinement(o, selectedGoal.id))} data-testid="add-refinement">
                  Add refinement
                </button>
              )}
            </p>
          )}
          {selectedGoal && (team || selectedGoal.meet || selectedGoal.behavior === "rendezvous") && (
            <p className="inspector-meet">
              <label htmlFor="goal-meet">Meeting id (rendezvous with the team)</label>
              <input
                id="goal-meet"
                value={selectedGoal.meet ?? ""}
                onChange={(e) => editOrders((o) => ({ ...o, goals: goals(o).map((g) => (g.id === selectedGoal.id ? patch(g, { meet: e.target.value.trim() }) : g)) }), `g:${selectedGoal.id}:meet`)}
                data-testid="goal-meet"
              />
              {team && selectedGoal.meet && scope.path.length === 0 && (
                <span className="hint" data-testid="meet-partners">
                  {partnersText(team, scope.member, selectedGoal.meet)}
                </span>
              )}
            </p>
          )}
          {selectedGoal ? (
            <GoalInspector
              key={selectedGoal.id}
              goal={selectedGoal}
              orders={orders}
              editOrders={editOrders}
              titleRef={titleRef}
              markers={markers}
              findings={local}
            />
          ) : selectedTerminal ? (
            <fieldset className="inspector" key={selectedTerminal.id}>
              <legend>Terminal {selectedTerminal.id}</legend>
              <label htmlFor="terminal-title">Title</label>
              <input
                id="terminal-title"
                value={selectedTerminal.title ?? ""}
                onChange={(e) => editOrders((o) => updateTerminal(o, selectedTerminal.id, { title: e.target.value }), `t:${selectedTerminal.id}:title`)}
              />
              <RefusedNote fieldId="terminal-title" />
              <label htmlFor="terminal-kind">Kind</label>
              <CommitSelect
                id="terminal-kind"
                value={selectedTerminal.kind}
                onCommit={(kind) => editOrders((o) => updateTerminal(o, selectedTerminal.id, { kind: kind as "complete" | "abort" }))}
              >
                <option value="complete">complete</option>
                <option value="abort">abort</option>
              </CommitSelect>
              {view.refinement && (
                <>
                  <label htmlFor="terminal-returns">Returns (the outcome of {scope.path[scope.path.length - 1]})</label>
                  <CommitSelect
                    id="terminal-returns"
                    value={isOutcome((selectedTerminal as { returns?: unknown }).returns) ? String((selectedTerminal as { returns?: unknown }).returns) : ""}
                    onCommit={(returns) => isOutcome(returns) && editOrders((o) => setReturns(o, selectedTerminal.id, returns))}
                  >
                    <option value="" disabled>
                      nothing (REFINE)
                    </option>
                    <option value="succeed">succeed</option>
                    <option value="fail">fail</option>
                    <option value="violate">violate</option>
                  </CommitSelect>
                </>
              )}
            </fieldset>
          ) : (
            <p className="hint">
              Select one goal or terminal to edit it. Drag from a goal's s (succeed, green), f (fail, orange) or c (violate,
              red) handle to the next goal or terminal.
            </p>
          )}
          </section>
          <section className="editor-findings-panel" aria-labelledby="editor-findings-title" tabIndex={0} data-testid="editor-findings-panel">
            <h3 id="editor-findings-title">Findings</h3>
            {report && (
              <p className={report.ok ? "verdict ok" : "verdict bad"} data-testid="editor-verdict">
                {refusal ? "As last saved: " : ""}
                {report.ok ? "Valid" : "Not valid"}: {plural(errors, "error")}, {plural(findings.length - errors, "warning")}.
                {report.paths ? ` ${plural(report.paths.count, "path")}.` : ""}
                {checkMs !== null && <span className="hint" data-testid="check-time"> Checked {checkMs} ms after the edit.</span>}
              </p>
            )}
            <FindingsList findings={findings} onPick={pickFinding} refused={refusal?.message ?? null} />
          </section>
        </aside>
      </div>
      <div className="editor-lower">
        <Tabs label="Orders beside the graph" tabs={PANELS.map((p) => ({ id: p.id, label: p.label }))} selected={panel} onSelect={setPanel}>
          {panel === "editor-constraints" && <ConstraintsPanel orders={panelOrders} editOrders={editPanelOrders} markers={markers} findings={findings} />}
          {panel === "editor-norms" && <NormsPanel orders={panelOrders} editOrders={editPanelOrders} markers={markers} known={known} />}
          {panel === "editor-areas" && <AreasPanel orders={panelOrders} editOrders={editPanelOrders} markers={markers} />}
          {panel === "editor-quantities" && <QuantitiesPanel orders={panelOrders} editOrders={editPanelOrders} />}
          {panel === "editor-vehicle" && <VehiclePanel orders={panelOrders} editOrders={editPanelOrders} markers={markers} />}
          {panel === "editor-mission" && <MissionPanel orders={panelOrders} editOrders={editPanelOrders} />}
          {panel === "editor-paths" && (
            <PathsPanel missionId={mission.id} orders={panelOrders} report={report} revision={saveState === "saved" ? revision : null} onHighlight={highlightPath} />
          )}
          {panel === "editor-plain" && (
            <section aria-labelledby="editor-plain-title" className="printable">
              <h3 id="editor-plain-title">Plain-language orders (as saved)</h3>
              <button type="button" onClick={() => window.print()}>
                Print orders
              </button>
              <pre className="orders-text" data-testid="editor-plain">
                {plain}
              </pre>
            </section>
          )}
        </Tabs>
      </div>
      {planOpen && <PlanDialog mission={mission} orders={panelOrders} onClose={() => setPlanOpen(false)} />}
      {shortcutsOpen && <ShortcutsDialog onClose={() => setShortcutsOpen(false)} />}
      {conflict && <ConflictDialog conflict={conflict} onReload={reloadTheirs} onResolve={resolve} />}
    </div>
  );
}
