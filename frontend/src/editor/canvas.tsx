/**
 * Canvas geometry of the graph editor: the canvas fills the window under the
 * toolbar, the inspector beside it is resizable, the minimap sits outside the graph (so it never
 * covers a handle) and can be hidden, zoom is bounded and nodes switch to a level of detail
 * whose titles stay legible, and new nodes go to free space beside the selection.
 */
import { MiniMap, useStore } from "@xyflow/react";
import { type KeyboardEvent, type PointerEvent, type RefObject, useEffect, useLayoutEffect, useState } from "react";

import type { Layout, Point } from "./graph";
import { GOAL_SIZE } from "./layout";

/** The least zoom of the canvas and of every fit. Below about 0.6 nodes show their title only,
 * drawn large enough to stay legible (styles.css, `--zoom`). */
export const MIN_ZOOM = 0.15;
export const FIT = { padding: 0.08, minZoom: MIN_ZOOM, maxZoom: 1.2 };
const MIN_CANVAS_PX = 360;

/**
 * The height of the canvas and the side column: the window's height less what stands
 * above them in the editor (toolbar, notices), so that, with the editor at the top of the
 * window, canvas, inspector and findings all fit in it; never below MIN_CANVAS_PX. The width is
 * the page's card's (no pull out of it: the canvas was once found at x = 0, outside the card).
 * On open the editor scrolls to the top of the window once, if it does not fit where it is.
 */
/** `shape`: anything above the canvas that changes its height (the scope bar). */
export function useEditorFrame(editor: RefObject<HTMLElement | null>, main: RefObject<HTMLElement | null>, shape: unknown = null): number {
  const [height, setHeight] = useState(620);
  useLayoutEffect(() => {
    const measure = () => {
      const top = editor.current?.getBoundingClientRect().top ?? 0;
      const mainTop = main.current?.getBoundingClientRect().top ?? 0;
      const above = Math.max(0, mainTop - top);
      // 28 px below: the card's padding and border, so that its bottom edge shows too.
      const next = Math.max(MIN_CANVAS_PX, Math.round(window.innerHeight - above - 28));
      setHeight((h) => (h === next ? h : next));
    };
    measure();
    const observer = typeof ResizeObserver === "undefined" ? null : new ResizeObserver(measure);
    if (observer && editor.current) observer.observe(editor.current.firstElementChild ?? editor.current);
    window.addEventListener("resize", measure);
    return () => {
      observer?.disconnect();
      window.removeEventListener("resize", measure);
    };
  }, [editor, main, shape]);
  useEffect(() => {
    const el = editor.current;
    if (!el) return;
    const box = el.getBoundingClientRect();
    if (box.top < 0 || box.top + (main.current?.offsetHeight ?? 0) > window.innerHeight) {
      window.scrollTo({ top: window.scrollY + box.top - 4, behavior: "instant" as ScrollBehavior });
    }
  }, [editor, main, shape]);
  return height;
}

/** Publishes the zoom as `--zoom` and a level of detail (`data-lod`) on the canvas element. */
export function ZoomDetail({ canvas }: { canvas: RefObject<HTMLElement | null> }) {
  const zoom = useStore((s) => s.transform[2]);
  useEffect(() => {
    const el = canvas.current;
    if (!el) return;
    el.style.setProperty("--zoom", String(zoom));
    el.dataset.lod = zoom < 0.6 ? "far" : "near";
  }, [zoom, canvas]);
  return null;
}

/** "Go to node" shows the node at this zoom: near detail, with its neighbours in the layout (a
 * successor 300 units to the right) inside even a 1024 px window's canvas. */
export const GOTO_ZOOM = 0.8;

/**
 * Where the pointer is while a connection is dragged, and whether it is over the canvas. A
 * handle that xyflow snaps to (its connection radius) may lie outside the canvas, under the
 * inspector, after the view auto-panned during the drag: a drop there must not connect.
 */
export function trackConnectPointer(canvas: () => HTMLElement | null): { start: () => void; inside: () => boolean } {
  let point: { x: number; y: number } | null = null;
  const move = (e: globalThis.PointerEvent | MouseEvent) => {
    point = { x: e.clientX, y: e.clientY };
  };
  const stop = () => {
    window.removeEventListener("pointermove", move, true);
    window.removeEventListener("pointerup", stop, true);
    window.setTimeout(() => {
      point = null;
    }, 0);
  };
  return {
    start: () => {
      point = null;
      window.addEventListener("pointermove", move, true);
      window.addEventListener("pointerup", stop, true);
    },
    inside: () => {
      const pane = canvas()?.querySelector(".react-flow")?.getBoundingClientRect();
      if (!point || !pane) return true;
      return point.x >= pane.left && point.x <= pane.right && point.y >= pane.top && point.y <= pane.bottom;
    },
  };
}

const SIDE_KEY = "countersign.editor.inspectorWidth";
const SIDE_MIN = 240;
const SIDE_MAX = 640;

/** The inspector's width, changed by dragging the splitter or with its arrow keys. */
export function useSideWidth(): [number, (w: number) => void] {
  const [width, setWidth] = useState(() => {
    const stored = Number(window.localStorage?.getItem(SIDE_KEY));
    // By default at most 30% of the window, so that a 1024 px window keeps a 700 px canvas.
    const fallback = Math.round(Math.min(352, Math.max(SIDE_MIN, window.innerWidth * 0.3)));
    return Number.isFinite(stored) && stored >= SIDE_MIN ? Math.min(stored, SIDE_MAX) : fallback;
  });
  const set = (w: number) => {
    const bounded = Math.round(Math.min(SIDE_MAX, Math.max(SIDE_MIN, w)));
    setWidth(bounded);
    try {
      window.localStorage.setItem(SIDE_KEY, String(bounded));
    } catch {
      /* storage disabled: the width holds for this page */
    }
  };
  return [width, set];
}

export function Splitter({ width, onWidth }: { width: number; onWidth: (w: number) => void }) {
  const start = (event: PointerEvent<HTMLDivElement>) => {
    const x0 = event.clientX;
    const w0 = width;
    const el = event.currentTarget;
    el.setPointerCapture(event.pointerId);
    const move = (e: globalThis.PointerEvent) => onWidth(w0 - (e.clientX - x0));
    const end = () => {
      el.removeEventListener("pointermove", move);
      el.removeEventListener("pointerup", end);
    };
    el.addEventListener("pointermove", move);
    el.addEventListener("pointerup", end);
  };
  const key = (event: KeyboardEvent<HTMLDivElement>) => {
    if (event.key === "ArrowLeft") onWidth(width + 24);
    else if (event.key === "ArrowRight") onWidth(width - 24);
    else return;
    event.preventDefault();
  };
  return (
    <div
      className="editor-splitter"
      role="separator"
      aria-orientation="vertical"
      aria-label="Resize the inspector (arrow keys)"
      aria-valuenow={width}
      aria-valuemin={SIDE_MIN}
      aria-valuemax={SIDE_MAX}
      tabIndex={0}
      onPointerDown={start}
      onKeyDown={key}
      data-testid="inspector-splitter"
    />
  );
}

/** Minimap colours: goals by their findings, terminals by kind (a grey box told nothing). */
function minimapColour(node: { type?: string; data: Record<string, unknown> }): string {
  if (node.data.severity === "error") return "#c9202c";
  if (node.data.severity === "warning") return "#d69e2e";
  if (node.type === "terminal") return node.data.terminalKind === "abort" ? "#8a2a2a" : "#1a7f37";
  return "#59606b";
}

/** The minimap, outside the graph's area (at the top of the side column), shown or hidden. Its
 * mask and background are given: xyflow's defaults come from CSS variables, and without them
 * the minimap drew as a black box. */
export function SideMinimap({ width, height = 110 }: { width: number; height?: number }) {
  const [shown, setShown] = useState(true);
  return (
    <div className="side-minimap">
      <button type="button" className="link-button" onClick={() => setShown(!shown)} aria-expanded={shown}>
        {shown ? "Hide minimap" : "Show minimap"}
      </button>
      {shown && (
        <MiniMap
          pannable
          zoomable
          ariaLabel="Minimap of the mission graph"
          nodeColor={minimapColour}
          nodeStrokeColor="#1b1f24"
          nodeStrokeWidth={2}
          nodeBorderRadius={6}
          bgColor="#fbfbfc"
          maskColor="rgba(31, 95, 191, 0.12)"
          maskStrokeColor="#1f5fbf"
          maskStrokeWidth={2}
          style={{ width, height, position: "static", margin: 0 }}
        />
      )}
    </div>
  );
}

interface Box {
  x: number;
  y: number;
  width: number;
  height: number;
}
const GAP = 40;

function overlaps(a: Box, b: Box): boolean {
  return a.x < b.x + b.width + GAP / 2 && b.x < a.x + a.width + GAP / 2 && a.y < b.y + b.height + GAP / 2 && b.y < a.y + a.height + GAP / 2;
}

/**
 * A free place for a new node: right of the selection (then below it, then further right), or
 * when nothing is selected near `around` (the centre of the view), never on an existing node.
 */
export function freePlace(layout: Layout, sizes: Record<string, { width: number; height: number }>, selected: Point | null, around: Point): Point {
  const boxes: Box[] = Object.entries(layout).map(([id, p]) => ({ ...p, ...(sizes[id] ?? GOAL_SIZE) }));
  const size = { width: GOAL_SIZE.width, height: 112 };
  const free = (p: Point) => !boxes.some((b) => overlaps({ ...p, ...size }, b));
  const dx = size.width + GAP * 2;
  const dy = size.height + GAP;
  const origin = selected ? { x: selected.x + dx, y: selected.y } : { x: Math.round(around.x - size.width / 2), y: Math.round(around.y - size.height / 2) };
  // Rings around the origin: columns to the right first, then rows below and above.
  for (let ring = 0; ring < 40; ring += 1) {
    for (let col = 0; col <= ring; col += 1) {
      for (const row of [ring - col, -(ring - col)]) {
        const p = { x: origin.x + col * dx, y: origin.y + row * dy };
        if (free(p)) return p;
      }
    }
  }
  const right = Math.max(0, ...boxes.map((b) => b.x + b.width));
  return { x: right + GAP * 2, y: origin.y };
}
