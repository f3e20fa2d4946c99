/**
 * The canvas's React Flow nodes and edges, kept in the store and synchronised with the draft,
 * the findings (markers) and the highlighted path. Unchanged nodes and edges keep their objects,
 * so React Flow re-renders only what changed.
 */
import { type Edge, MarkerType, Position } from "@xyflow/react";
import { useEffect, useLayoutEffect, useMemo } from "react";

import type { Finding } from "../api/client";
import {
  edgeMarkers,
  type GraphEdge,
  type GraphNode,
  markersBySubject,
  ordersToGraph,
  OUTCOME_LABEL,
  OUTCOME_LETTER,
  type Outcome,
  OUTCOMES,
  pathElements,
} from "./graph";
import { loopsOf } from "./findingGroups";
import type { NodeData } from "./nodes";
import { findingsAt, isOutcome, localFindings } from "./scope";
import { useEditor, useEditorApi } from "./store";
import { useScopedDraft } from "./useScopedDraft";

/** Above this many goals the canvas renders only what is in view and opens at the start goal. */
export const LARGE_GOALS = 200;
const COLOURS: Record<Outcome, string> = { succeed: "#1a7f37", fail: "#c25e00", violate: "#c9202c" };
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

export type Markers = ReturnType<typeof markersBySubject>;

export interface FlowElements {
  graph: { nodes: GraphNode[]; edges: GraphEdge[] };
  /** The findings that concern the scope shown (all of them at the mission). */
  findings: Finding[];
  /** Those findings with subjects as the canvas at this scope names them. */
  local: Finding[];
  markers: Markers;
}

/** The goals in the scope of the constraint being picked (marked on the canvas). */
function scopeOf(orders: { constraints?: { id: string; applies_to?: unknown }[] | null }, constraint: string | null): Set<string> {
  const c = constraint ? (orders.constraints ?? []).find((x) => x.id === constraint) : undefined;
  return new Set(c && Array.isArray(c.applies_to) ? (c.applies_to as string[]) : []);
}

// Length: the diff of nodes and edges keeps unchanged objects in one pass.
export function useFlowElements(large: boolean): FlowElements {
  const store = useEditorApi();
  const draft = useScopedDraft();
  const report = useEditor((s) => s.report);
  const highlight = useEditor((s) => s.highlight);
  const placed = useEditor((s) => s.placed);
  const scopePick = useEditor((s) => s.scopePick);
  const inScope = useMemo(() => scopeOf(draft.orders, scopePick), [draft.orders, scopePick]);
  const focus = useEditor((s) => s.focus);

  const findings = useMemo(() => findingsAt(report?.findings ?? [], draft.prefix, draft.team), [report, draft.prefix, draft.team]);
  // A finding inside a refinement (`G1/G1.1`) marks the refined goal that holds it (G1).
  const nested = useMemo(() => (draft.orders.goals ?? []).some((g) => g.refines), [draft.orders]);
  const local = useMemo(
    () => (draft.prefix === "" && !nested ? findings : localFindings(findings, draft.prefix)),
    [findings, draft.prefix, nested],
  );
  // What a node shows beyond its title: a refined goal, a meeting, what a terminal returns.
  const extras = useMemo(() => {
    const out = new Map<string, { refined: boolean; meet: string | null; returns: string | null }>();
    for (const g of draft.orders.goals ?? []) out.set(g.id, { refined: Boolean(g.refines), meet: g.meet ?? null, returns: null });
    for (const t of draft.orders.terminals ?? []) {
      const returns = (t as { returns?: unknown }).returns;
      out.set(t.id, { refined: false, meet: null, returns: draft.refinement ? (isOutcome(returns) ? returns : "nothing") : null });
    }
    return out;
  }, [draft.orders, draft.refinement]);
  useEffect(() => {
    if (report) performance.mark("editor:findings-rendered");
  }, [report]);
  const markers = useMemo(() => markersBySubject(local), [local]);
  const graph = useMemo(() => ordersToGraph(draft.orders, draft.layout), [draft.orders, draft.layout]);
  const edgeMarks = useMemo(() => edgeMarkers(local, graph.edges), [local, graph.edges]);
  const onPath = useMemo(() => (highlight ? pathElements(highlight.path) : null), [highlight]);
  // Loops are drawn once, as a highlighted cycle (a halo under the edges inside one loop), not
  // as a "✖ G7" label on every edge.
  const loopEdges = useMemo(() => {
    const inLoop = new Set<string>();
    for (const loop of loopsOf(local)) {
      const goals = new Set(loop.goals);
      for (const e of graph.edges) if (goals.has(e.source) && goals.has(e.target)) inLoop.add(e.id);
    }
    return inLoop;
  }, [local, graph.edges]);
  // "Focus this goal": the goal, its predecessors and successors stay; the rest fades.
  const near = useMemo(() => {
    if (!focus) return null;
    const nodes = new Set([focus]);
    for (const e of graph.edges) {
      if (e.source === focus) nodes.add(e.target);
      if (e.target === focus) nodes.add(e.source);
    }
    return nodes;
  }, [focus, graph.edges]);

  // Before the browser paints: markers show in the same frame as the findings list.
  useLayoutEffect(() => {
    if (!placed) return;
    const { setNodes, setEdges } = store.getState();
    setNodes((previous) => {
      const before = new Map(previous.map((n) => [n.id, n]));
      return graph.nodes.map((n) => {
        const old = before.get(n.id);
        const mark = markers.get(n.id);
        const extra = extras.get(n.id);
        const data: NodeData = {
          refined: extra?.refined ?? false,
          meet: extra?.meet ?? null,
          returns: extra?.returns ?? null,
          label: n.label,
          start: n.start,
          codes: mark?.codes ?? [],
          severity: mark?.severity ?? null,
          terminalKind: n.terminalKind,
        };
        const lit = onPath?.nodes.has(n.id) ?? false;
        const ariaLabel = `${n.kind === "goal" ? "Goal" : "Terminal"} ${n.id}: ${n.label}${n.start ? " (start)" : ""}${extra?.refined ? "; refined (double-click to open)" : ""}${
          extra?.meet ? `; meeting ${extra.meet}` : ""
        }${extra?.returns ? `; returns ${extra.returns}` : ""}${
          mark ? `; findings ${mark.codes.join(", ")}` : ""
        }${lit ? "; on the highlighted path" : ""}`;
        const className = `${lit ? "on-path" : ""}${inScope.has(n.id) ? " in-scope" : ""}${near && !near.has(n.id) ? " dimmed" : ""}`.trim();
        if (
          old &&
          old.type === n.kind &&
          old.position.x === n.position.x &&
          old.position.y === n.position.y &&
          old.ariaLabel === ariaLabel &&
          (old.className ?? "") === className &&
          old.data.severity === data.severity &&
          old.data.terminalKind === data.terminalKind &&
          old.data.refined === data.refined &&
          old.data.meet === data.meet &&
          old.data.returns === data.returns &&
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
          ...(large ? PRESET[n.kind] : {}),
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
        .map((e): Edge => {
          const old = before.get(e.id);
          const loop = loopEdges.has(e.id);
          // A loop's edges carry its halo instead of the G7 code; other codes stay on the label.
          const marked = edgeMarks.get(e.id);
          const codes = (marked?.codes ?? []).filter((c) => c !== "G7");
          const mark = marked && codes.length > 0 ? { ...marked, codes } : undefined;
          const lit = onPath?.edges.has(e.id) ?? false;
          const colour = COLOURS[e.outcome];
          const faded = near !== null && e.source !== focus && e.target !== focus;
          const label = `${OUTCOME_LETTER[e.outcome]}${mark ? ` ${mark.severity === "error" ? "✖" : "⚠"} ${mark.codes.join(" ")}` : ""}${lit ? " ●" : ""}`;
          const className = `edge-${e.outcome}${mark ? ` edge-marked edge-marked-${mark.severity}` : ""}${lit ? " edge-on-path" : ""}${loop ? " edge-loop" : ""}${faded ? " dimmed" : ""}`;
          const ariaLabel = `${e.source} ${OUTCOME_LABEL[e.outcome]} to ${e.target}${mark ? `; findings ${mark.codes.join(", ")}` : ""}${
            loop ? "; in a loop (G7)" : ""
          }${lit ? "; on the highlighted path" : ""}`;
          // Unchanged edges keep their object (the id names source, outcome and target; the
          // style follows from the label and class).
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
            data: { loop },
            // Tab reaches the nodes, not the edges (it walked every edge first); an
            // edge is changed in its goal's inspector (the outcome's next goal).
            focusable: false,
            style: { stroke: colour, strokeWidth: lit ? 5 : mark || loop ? 3 : 2, strokeDasharray: mark ? "6 4" : undefined },
            labelStyle: { fill: colour, fontWeight: 700 },
            markerEnd: { type: MarkerType.ArrowClosed, color: colour },
            ariaLabel,
            selected: old?.selected ?? false,
          };
        });
    });
  }, [store, graph, markers, edgeMarks, onPath, placed, large, loopEdges, near, focus, inScope, extras]);

  return { graph, findings, local, markers };
}
