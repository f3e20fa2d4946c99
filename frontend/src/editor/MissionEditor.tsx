/**
 * The graph editor of a mission draft (operators). The pure logic lives in graph.ts,
 * history.ts and layout.ts; this component wires it to React Flow and the API: every edit
 * sends the new orders to /api/validate at once (from the event handler, before React renders
 * the edit), then saves the draft with If-Match; typing waits for a pause first. The plain
 * orders are fetched only while their tab is open.
 */
import "@xyflow/react/dist/style.css";

import {
  applyEdgeChanges,
  applyNodeChanges,
  Background,
  type Connection,
  Controls,
  type Edge,
  type EdgeChange,
  MarkerType,
  MiniMap,
  type Node,
  Position,
  type NodeChange,
  ReactFlow,
  ReactFlowProvider,
  useReactFlow,
} from "@xyflow/react";
import { type KeyboardEvent, useCallback, useEffect, useLayoutEffect, useMemo, useRef, useState } from "react";

import { api, exportHref, fetchText, type Finding, type MissionDetail, unwrap } from "../api/client";
import { ErrorMessage } from "../components/Status";
import { plural } from "../format";
import {
  addGoal,
  addTerminal,
  checkConnection,
  connect,
  deleteNodes,
  describeDifferences,
  disconnect,
  edgeMarkers,
  findingPath,
  goals,
  type Layout,
  markersBySubject,
  type Orders,
  ordersToGraph,
  OUTCOME_LABEL,
  OUTCOME_LETTER,
  type Outcome,
  OUTCOMES,
  type PathLike,
  pathElements,
  terminals,
  updateTerminal,
} from "./graph";
import { knownQuantities } from "./expr";
import { canRedo, canUndo, push, redo, reset, undo } from "./history";
import { copyGoals, pasteGoals, readClip } from "./model";
import { AreasPanel, MissionPanel, NormsPanel, QuantitiesPanel, VehiclePanel } from "./panels";
import { PathsPanel } from "./PathsPanel";
import { ImportMenu, NewFromExample, readOrdersFile } from "./ImportMenu";
import { PlanDialog } from "./PlanDialog";
import { Tabs } from "../components/Tabs";
import { autoLayout } from "./layout";
import { EDGE_TYPES, NODE_TYPES, type NodeData } from "./nodes";
import { type Conflict, ConflictDialog } from "./ConflictDialog";
import { type Draft, isLaidOut, useDraftHistory } from "./useDraftHistory";
import { useServerCheck } from "./useServerCheck";
import { ConstraintsPanel, FindingsList, GoalInspector } from "./Inspector";
import { ExportMenu, ToolbarMenu } from "./Toolbar";

const SAVE_DELAY_MS = 250;
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
/** Node sizes and handle positions as the CSS draws them (goal 220 x 112, handles 18 px). */
const PRESET = {
  goal: {
    initialWidth: 220,
    initialHeight: 112,
    handles: [
      { id: "in", type: "target" as const, position: Position.Left, x: -6, y: 50, width: 12, height: 12 },
      ...OUTCOMES.map((o, i) => ({ id: o, type: "source" as const, position: Position.Right, x: 211, y: 28 * (i + 1) - 9, width: 18, height: 18 })),
    ],
  },
  terminal: {
    initialWidth: 160,
    initialHeight: 60,
    handles: [{ id: "in", type: "target" as const, position: Position.Left, x: -6, y: 24, width: 12, height: 12 }],
  },
};
/** Above this many goals the canvas renders only what is in view and opens at the start goal. */
const LARGE_GOALS = 200;
const COLOURS: Record<Outcome, string> = { succeed: "#1a7f37", fail: "#c25e00", violate: "#c9202c" };

/** `onSaved` gets the mission as the save answered it (the page shows it without re-reading). */
export default function MissionEditor(props: { mission: MissionDetail; onSaved: (saved: MissionDetail) => void }) {
  return (
    <ReactFlowProvider>
      <Editor {...props} />
    </ReactFlowProvider>
  );
}

type SaveState = "saved" | "pending" | "saving" | "conflict" | "error";

function Editor({ mission, onSaved }: { mission: MissionDetail; onSaved: (saved: MissionDetail) => void }) {
  const flow = useReactFlow();
  const { history, latest, updateHistory } = useDraftHistory(mission);
  const draft = history.present;
  const orders = draft.orders;
  const revision = useRef(mission.revision);
  const [savedRevision, setSavedRevision] = useState(mission.revision);
  const [saveState, setSaveState] = useState<SaveState>("saved");
  const [saveError, setSaveError] = useState<unknown>(null);
  const [conflict, setConflict] = useState<Conflict | null>(null);
  const [plain, setPlain] = useState<string>("");
  const [notice, setNotice] = useState<string>("");
  const saving = useRef(false);
  const again = useRef(false);

  useEffect(() => {
    performance.mark("editor:mounted");
  }, []);

  const { report, checkMs, lastChecked, editedAt, refreshChecks, check } = useServerCheck(mission, latest, setSaveError);

  const save = useCallback(async () => {
    if (saving.current) {
      again.current = true;
      return;
    }
    saving.current = true;
    setSaveState("saving");
    const sent = latest.current;
    try {
      // Saved once checked: the save then finds the report cached instead of validating the
      // same orders a second time beside the check.
      const reported = await check(sent.orders);
      const result = await api.PUT("/api/missions/{mission_id}/draft", {
        params: { path: { mission_id: mission.id }, header: { "if-match": `"${revision.current}"` } },
        body: { orders: sent.orders, layout: sent.layout },
      });
      if (result.response.status === 412) {
        const theirs = unwrap(await api.GET("/api/missions/{mission_id}", { params: { path: { mission_id: mission.id } } }));
        const differences = describeDifferences(latest.current.orders, theirs.orders as Orders);
        setConflict({ theirs, differences });
        setSaveState("conflict");
        again.current = false;
        return;
      }
      const saved = unwrap(result);
      revision.current = saved.revision;
      setSavedRevision(saved.revision);
      setSaveError(null);
      setSaveState(latest.current === sent ? "saved" : "pending");
      onSaved(saved);
      // The check above reported these orders; re-read the report only if it failed.
      if (!reported && latest.current === sent) await refreshChecks();
    } catch (e) {
      setSaveError(e);
      setSaveState("error");
    } finally {
      saving.current = false;
      if (again.current) {
        again.current = false;
        void save();
      }
    }
  }, [mission.id, onSaved, refreshChecks, check]);

  // Every change of the present draft (edit, undo, redo) is checked and saved: discrete edits
  // at once, from the event handler; typing in a field after a short pause.
  const inConflict = useRef(false);
  inConflict.current = conflict !== null;
  const saveTimer = useRef<number | undefined>(undefined);
  useEffect(() => () => window.clearTimeout(saveTimer.current), []);
  const changed = useCallback(
    (group?: string) => {
      editedAt.current = performance.now();
      performance.mark("editor:edit");
      if (inConflict.current) return;
      window.clearTimeout(saveTimer.current);
      setSaveState("pending");
      if (group) {
        saveTimer.current = window.setTimeout(() => void save(), SAVE_DELAY_MS);
        return;
      }
      void check(latest.current.orders);
      void save();
    },
    [save, check],
  );

  const edit = useCallback(
    (change: (d: Draft) => Draft, group?: string) => {
      updateHistory((h) => push(h, change(h.present), group ? { group } : {}));
      changed(group);
    },
    [updateHistory, changed],
  );
  const editOrders = useCallback(
    (change: (o: Orders) => Orders, group?: string) => edit((d) => ({ ...d, orders: change(d.orders) }), group),
    [edit],
  );

  // Lay out a draft that has no positions yet (new or imported), without an undo step.
  // Small orders open fitted to the canvas; large ones open at the start goal at a readable
  // zoom, so that only the nodes in view are rendered (the toolbar's "Zoom to fit" shows all).
  const laidOut = useRef(false);
  const large = useRef(goals(mission.orders as Orders).length > LARGE_GOALS);
  const openView = useRef(false);
  const [ready, setReady] = useState(false);
  // Until the opened draft has positions, the canvas gets no nodes (they would all render,
  // stacked, with every edge crossing the view, only to move a moment later).
  const [placed, setPlaced] = useState(() => isLaidOut(draft));
  // Positions computed on open are saved with the draft (once), so that it opens as laid out.
  const savedLayout = useRef((mission.layout ?? {}) as Layout);
  const saveComputedLayout = useCallback(
    (layout: Layout) => {
      if (inConflict.current || Object.keys(layout).every((id) => savedLayout.current[id])) return;
      setSaveState("pending");
      void save();
    },
    [save],
  );
  useEffect(() => {
    if (ready) performance.mark("editor:ready");
  }, [ready]);
  useEffect(() => {
    if (laidOut.current) return;
    laidOut.current = true;
    if (isLaidOut(draft)) {
      openView.current = true;
      saveComputedLayout(draft.layout); // a large draft laid out as it opened (above)
      return;
    }
    void autoLayout(orders).then((layout) => {
      openView.current = true;
      updateHistory((h) => reset({ ...h.present, layout: { ...layout, ...h.present.layout } }));
      setPlaced(true);
      saveComputedLayout(layout);
    }, () => {
      openView.current = true;
      setPlaced(true); // no layout: show the default positions rather than nothing
    });
  }, [orders, draft.layout, flow, updateHistory, saveComputedLayout]);

  // ---- React Flow nodes and edges, synchronised with the draft ----
  const findings = useMemo(() => report?.findings ?? [], [report]);
  useEffect(() => {
    if (report) performance.mark("editor:findings-rendered");
  }, [report]);
  const markers = useMemo(() => markersBySubject(findings), [findings]);
  const graph = useMemo(() => ordersToGraph(orders, draft.layout), [orders, draft.layout]);
  const edgeMarks = useMemo(() => edgeMarkers(findings, graph.edges), [findings, graph.edges]);
  const [highlight, setHighlight] = useState<{ path: PathLike; label: string } | null>(null);
  const onPath = useMemo(() => (highlight ? pathElements(highlight.path) : null), [highlight]);
  const highlightPath = useCallback((path: PathLike | null, label = "") => setHighlight(path ? { path, label } : null), []);
  const [nodes, setNodes] = useState<Node<NodeData>[]>([]);
  const [edges, setEdges] = useState<Edge[]>([]);
  const selectNext = useRef<string[] | null>(null);

  // Before the browser paints: markers show in the same frame as the findings list.
  useLayoutEffect(() => {
    if (!placed) return;
    setNodes((previous) => {
      const before = new Map(previous.map((n) => [n.id, n]));
      return graph.nodes.map((n) => {
        const old = before.get(n.id);
        const mark = markers.get(n.id);
        const data: NodeData = {
          label: n.label,
          start: n.start,
          codes: mark?.codes ?? [],
          severity: mark?.severity ?? null,
          terminalKind: n.terminalKind,
        };
        const lit = onPath?.nodes.has(n.id) ?? false;
        const ariaLabel = `${n.kind === "goal" ? "Goal" : "Terminal"} ${n.id}: ${n.label}${n.start ? " (start)" : ""}${
          mark ? `; findings ${mark.codes.join(", ")}` : ""
        }${lit ? "; on the highlighted path" : ""}`;
        const className = lit ? "on-path" : "";
        // Unchanged nodes keep their object, so React Flow re-renders only what changed.
        if (
          old &&
          old.type === n.kind &&
          old.position.x === n.position.x &&
          old.position.y === n.position.y &&
          old.ariaLabel === ariaLabel &&
          (old.className ?? "") === className &&
          old.data.severity === data.severity &&
          old.data.terminalKind === data.terminalKind &&
          old.data.codes.join() === data.codes.join()
        ) {
          return old;
        }
        return {
          id: n.id,
          type: n.kind,
          position: n.position,
          // Large missions: sizes and handle positions are given, so React Flow need not render
          // every node once to measure it; only the nodes in view are rendered.
          ...(large.current ? PRESET[n.kind] : {}),
          data,
          ariaLabel,
          className,
          selected: old?.selected ?? false,
          ...(old?.measured ? { measured: old.measured } : {}),
        };
      });
    });
    setEdges((previous) => {
      const before = new Map(previous.map((e) => [e.id, e]));
      return graph.edges
        .filter((e) => !e.dangling)
        .map((e) => {
          const old = before.get(e.id);
          const mark = edgeMarks.get(e.id);
          const lit = onPath?.edges.has(e.id) ?? false;
          const colour = COLOURS[e.outcome];
          const label = `${OUTCOME_LETTER[e.outcome]}${mark ? ` ${mark.severity === "error" ? "✖" : "⚠"} ${mark.codes.join(" ")}` : ""}${lit ? " ●" : ""}`;
          const className = `edge-${e.outcome}${mark ? ` edge-marked edge-marked-${mark.severity}` : ""}${lit ? " edge-on-path" : ""}`;
          const ariaLabel = `${e.source} ${OUTCOME_LABEL[e.outcome]} to ${e.target}${mark ? `; findings ${mark.codes.join(", ")}` : ""}${
            lit ? "; on the highlighted path" : ""
          }`;
          // Unchanged edges keep their object (the id names source, outcome and target; the
          // style follows from the label and class), so React Flow re-renders only what changed.
          if (old && old.label === label && old.className === className && old.ariaLabel === ariaLabel) return old;
          return {
            id: e.id,
            type: "outcome",
            source: e.source,
            sourceHandle: e.outcome,
            target: e.target,
            targetHandle: "in",
            label,
            className,
            style: { stroke: colour, strokeWidth: lit ? 5 : mark ? 3 : 2, strokeDasharray: mark ? "6 4" : undefined },
            labelStyle: { fill: colour, fontWeight: 700 },
            markerEnd: { type: MarkerType.ArrowClosed, color: colour },
            ariaLabel,
            selected: old?.selected ?? false,
          };
        });
    });
  }, [graph, markers, edgeMarks, onPath, placed]);

  const onNodesChange = useCallback((changes: NodeChange<Node<NodeData>>[]) => {
    setNodes((ns) => applyNodeChanges(changes.filter((c) => c.type !== "remove"), ns));
  }, []);
  const onEdgesChange = useCallback((changes: EdgeChange[]) => {
    setEdges((es) => applyEdgeChanges(changes.filter((c) => c.type !== "remove"), es));
  }, []);

  const select = useCallback((ids: string[]) => {
    setNodes((ns) => ns.map((n) => ({ ...n, selected: ids.includes(n.id) })));
    setEdges((es) => es.map((e) => ({ ...e, selected: false })));
  }, []);

  // Zoom to fit once the nodes carry their new positions (after an auto layout).
  const fitPending = useRef(false);
  useEffect(() => {
    if (openView.current && nodes.length > 0) {
      openView.current = false;
      const start = nodes.find((n) => n.data.start) ?? nodes[0]!;
      window.requestAnimationFrame(() => {
        if (large.current) void flow.setCenter(start.position.x + 300, start.position.y + 150, { zoom: 0.6 });
        else void flow.fitView({ padding: 0.15 });
        setReady(true);
      });
      return;
    }
    if (!fitPending.current) return;
    fitPending.current = false;
    window.requestAnimationFrame(() => {
      void flow.fitView({ padding: 0.15 });
      setReady(true);
    });
  }, [nodes, flow]);

  // Select what was just added once its node exists (the inspector then shows it).
  useEffect(() => {
    const wanted = selectNext.current;
    if (wanted && wanted.every((id) => nodes.some((n) => n.id === id))) {
      selectNext.current = null;
      select(wanted);
    }
  }, [nodes, select]);

  const [gotoText, setGotoText] = useState("");
  const [panel, setPanel] = useState("editor-constraints");
  // The plain orders (as saved): fetched when their tab opens and after each save while open.
  const plainShown = panel === "editor-plain";
  useEffect(() => {
    if (!plainShown) return;
    let current = true;
    fetchText(exportHref(mission.id, "plain")).then((text) => current && setPlain(text), (e: unknown) => current && setSaveError(e));
    return () => {
      current = false;
    };
  }, [plainShown, savedRevision, mission.id]);
  const [planOpen, setPlanOpen] = useState(false);
  const known = useMemo(() => knownQuantities(orders), [orders]);
  const goTo = (id: string) => {
    const node = graph.nodes.find((n) => n.id === id);
    if (!node) {
      setConnectMessage(`No node ${id}.`);
      return;
    }
    select([id]);
    void flow.setCenter(node.position.x + 110, node.position.y + 56, { zoom: Math.max(flow.getZoom(), 0.8) });
  };

  const selectedNodes = nodes.filter((n) => n.selected).map((n) => n.id);
  const selectedId = selectedNodes.length === 1 ? selectedNodes[0] : undefined;

  const [connectMessage, setConnectMessage] = useState("");
  const onConnect = useCallback(
    (c: Connection) => {
      const result = connect(latest.current.orders, c.source, c.sourceHandle ?? "", c.target);
      if (!result.check.ok) {
        setConnectMessage(result.check.reason ?? "That connection is not allowed.");
        return;
      }
      setConnectMessage(`Connected ${c.source} ${c.sourceHandle} to ${c.target}.`);
      // Applied to the newest orders (a previous edit may not have rendered yet).
      editOrders((o) => connect(o, c.source, c.sourceHandle ?? "", c.target).orders);
    },
    [editOrders],
  );
  const isValidConnection = useCallback(
    (c: Connection | Edge) => checkConnection(latest.current.orders, c.source, c.sourceHandle, c.target).ok,
    [],
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

  const placeNew = useCallback((): { x: number; y: number } => {
    const pane = document.querySelector(".editor-canvas")?.getBoundingClientRect();
    const centre = pane
      ? flow.screenToFlowPosition({ x: pane.left + pane.width / 2, y: pane.top + pane.height / 2 })
      : { x: 0, y: 0 };
    const n = Object.keys(latest.current.layout).length % 6;
    return { x: Math.round(centre.x - 110 + n * 24), y: Math.round(centre.y - 48 + n * 24) };
  }, [flow]);

  const titleRef = useRef<HTMLInputElement>(null);
  const addGoalNode = () => {
    const at = placeNew();
    const { orders: next, id } = addGoal(latest.current.orders);
    selectNext.current = [id];
    edit((d) => ({ orders: next, layout: { ...d.layout, [id]: at } }));
    window.setTimeout(() => titleRef.current?.select(), 50);
  };
  const addTerminalNode = (kind: "complete" | "abort") => {
    const at = placeNew();
    const { orders: next, id } = addTerminal(latest.current.orders, kind);
    selectNext.current = [id];
    edit((d) => ({ orders: next, layout: { ...d.layout, [id]: at } }));
  };
  const deleteSelected = () => {
    const nodeIds = nodes.filter((n) => n.selected).map((n) => n.id);
    const edgeList = edges.filter((e) => e.selected);
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
    const layout = await autoLayout(latest.current.orders, sizes);
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
      const next = { ...read, id: mission.id } as Orders;
      const layout = await autoLayout(next);
      setReady(false);
      fitPending.current = true;
      edit(() => ({ orders: next, layout }));
      const codes = [...new Set(found.map((f) => f.code).filter(Boolean))];
      setNotice(
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
    else return;
    event.preventDefault();
  };

  // ---- Conflict resolution ----
  const reloadTheirs = () => {
    if (!conflict) return;
    revision.current = conflict.theirs.revision;
    setSavedRevision(conflict.theirs.revision);
    updateHistory(() => reset({ orders: conflict.theirs.orders as Orders, layout: (conflict.theirs.layout ?? {}) as Layout }));
    lastChecked.current = conflict.theirs.orders as Orders;
    setConflict(null);
    setSaveState("saved");
    setNotice("Reloaded the draft someone else saved.");
    void refreshChecks();
    onSaved(conflict.theirs);
  };
  const keepMine = () => {
    if (!conflict) return;
    revision.current = conflict.theirs.revision;
    inConflict.current = false;
    setConflict(null);
    setNotice("Your version replaced theirs.");
    void save();
  };

  // ---- Copy, paste, duplicate (clipboard JSON; also kept in localStorage between missions) ----
  const copySelected = () => {
    const clip = copyGoals(latest.current.orders, latest.current.layout, selectedNodes);
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
    const result = pasteGoals(latest.current.orders, latest.current.layout, clip);
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
    const clip = copyGoals(latest.current.orders, latest.current.layout, selectedNodes);
    if (clip) pasteClip(JSON.stringify(clip));
  };

  const nodeIds = useRef(new Set<string>());
  nodeIds.current = new Set(graph.nodes.map((n) => n.id));
  const pickFinding = useCallback(
    (f: Finding) => {
      select(f.subjects);
      const shown = f.subjects.filter((id) => nodeIds.current.has(id));
      if (shown.length > 0) void flow.fitView({ nodes: shown.map((id) => ({ id })), padding: 0.5, maxZoom: 1 });
      const path = findingPath(f);
      highlightPath(path, path ? `${f.code} counterexample` : "");
    },
    [select, flow, highlightPath],
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
    <div className="editor">
      <div className="editor-toolbar" role="toolbar" aria-label="Graph editing">
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
          <button type="button" className="menu-item" onClick={() => void flow.fitView({ padding: 0.15 })}>
            Zoom to fit
          </button>
          <button type="button" className="menu-item" onClick={() => setPlanOpen(true)}>
            Plan survey…
          </button>
          <ImportMenu onImport={importFile} busy={importing} />
          <ExportMenu missionId={mission.id} saved={saveState === "saved"} />
          <NewFromExample />
        </ToolbarMenu>
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
          <button type="button" onClick={() => setHighlight(null)}>
            Clear highlight
          </button>
        </p>
      )}
      <div className="editor-main">
        <div
          className="editor-canvas"
          tabIndex={0}
          role="group"
          aria-label="Mission graph. Shortcuts: G add goal, Delete remove selection, Ctrl+C copy, Ctrl+V paste, Ctrl+D duplicate, Ctrl+Z undo, Ctrl+Shift+Z or Ctrl+Y redo, L auto layout; Tab moves between nodes, Enter selects, arrows move."
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
            isValidConnection={isValidConnection}
            onNodeDragStop={onNodeDragStop}
            deleteKeyCode={null}
            minZoom={0.05}
            fitView={!large.current}
            onlyRenderVisibleElements={nodes.length > LARGE_GOALS}
            proOptions={{ hideAttribution: true }}
          >
            <Background />
            <MiniMap pannable zoomable ariaLabel="Minimap of the mission graph" />
            <Controls showInteractive={false} />
          </ReactFlow>
        </div>
        <aside className="editor-side" aria-label="Inspector">
          <h3>Inspector</h3>
          {selectedGoal ? (
            <GoalInspector
              key={selectedGoal.id}
              goal={selectedGoal}
              orders={orders}
              editOrders={editOrders}
              titleRef={titleRef}
              markers={markers}
              findings={findings}
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
              <label htmlFor="terminal-kind">Kind</label>
              <select
                id="terminal-kind"
                value={selectedTerminal.kind}
                onChange={(e) => editOrders((o) => updateTerminal(o, selectedTerminal.id, { kind: e.target.value as "complete" | "abort" }))}
              >
                <option value="complete">complete</option>
                <option value="abort">abort</option>
              </select>
            </fieldset>
          ) : (
            <p className="hint">
              Select one goal or terminal to edit it. Drag from a goal's s (succeed, green), f (fail, orange) or c (violate,
              red) handle to the next goal or terminal.
            </p>
          )}
          <section aria-labelledby="editor-findings-title">
            <h3 id="editor-findings-title">Findings</h3>
            {report && (
              <p className={report.ok ? "verdict ok" : "verdict bad"} data-testid="editor-verdict">
                {report.ok ? "Valid" : "Not valid"}: {plural(errors, "error")}, {plural(findings.length - errors, "warning")}.
                {report.paths ? ` ${plural(report.paths.count, "path")}.` : ""}
                {checkMs !== null && <span className="hint" data-testid="check-time"> Checked {checkMs} ms after the edit.</span>}
              </p>
            )}
            <FindingsList findings={findings} onPick={pickFinding} />
          </section>
        </aside>
      </div>
      <div className="editor-lower">
        <Tabs label="Orders beside the graph" tabs={PANELS.map((p) => ({ id: p.id, label: p.label }))} selected={panel} onSelect={setPanel}>
          {panel === "editor-constraints" && <ConstraintsPanel orders={orders} editOrders={editOrders} markers={markers} findings={findings} />}
          {panel === "editor-norms" && <NormsPanel orders={orders} editOrders={editOrders} markers={markers} known={known} />}
          {panel === "editor-areas" && <AreasPanel orders={orders} editOrders={editOrders} markers={markers} />}
          {panel === "editor-quantities" && <QuantitiesPanel orders={orders} editOrders={editOrders} />}
          {panel === "editor-vehicle" && <VehiclePanel orders={orders} editOrders={editOrders} markers={markers} />}
          {panel === "editor-mission" && <MissionPanel orders={orders} editOrders={editOrders} />}
          {panel === "editor-paths" && (
            <PathsPanel missionId={mission.id} orders={orders} report={report} revision={saveState === "saved" ? revision.current : null} onHighlight={highlightPath} />
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
      {planOpen && <PlanDialog mission={mission} orders={orders} onClose={() => setPlanOpen(false)} />}
      {conflict && <ConflictDialog conflict={conflict} onReload={reloadTheirs} onKeepMine={keepMine} />}
    </div>
  );
}
