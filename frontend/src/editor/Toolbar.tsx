/** The editor toolbar's menus: a generic menu and the export downloads (with an SVG of the canvas). */
import { type ReactNode, type RefObject, useEffect, useLayoutEffect, useRef, useState } from "react";

import { exportHref } from "../api/client";

/** A toolbar menu: a summary that opens a column of actions. Choosing an action (a button with
 * class menu-item), Escape, or a press outside the menu closes it. */
export function ToolbarMenu({ label, children }: { label: string; children: ReactNode }) {
  const ref = useRef<HTMLDetailsElement>(null);
  const body = useRef<HTMLDivElement>(null);
  const [open, setOpen] = useState(false);
  useKeptInWindow(body, open);
  useEffect(() => {
    if (!open) return;
    const outside = (event: PointerEvent) => {
      if (ref.current && !ref.current.contains(event.target as globalThis.Node)) ref.current.open = false;
    };
    document.addEventListener("pointerdown", outside);
    return () => document.removeEventListener("pointerdown", outside);
  }, [open]);
  return (
    <details
      ref={ref}
      className="toolbar-menu"
      onToggle={(e) => setOpen(e.currentTarget.open)}
      onKeyDown={(e) => {
        if (e.key !== "Escape" || !ref.current?.open) return;
        e.stopPropagation();
        ref.current.open = false;
        ref.current.querySelector("summary")?.focus();
      }}
      onClick={(e) => {
        if ((e.target as HTMLElement).closest(".menu-item") && ref.current) ref.current.open = false;
      }}
    >
      <summary>{label}</summary>
      <div ref={body} className="toolbar-menu-body" role="group" aria-label={label}>
        {children}
      </div>
    </details>
  );
}

/** Moves an open menu's body left by as much as it would reach past the window's right edge
 * (never past its left edge), also when it grows (a submenu opened inside it). A body past the
 * edge widens the page; closing the menu then narrows it again and the page scrolls back, so
 * the press outside that closed it ends on another control than the one it began on. */
function useKeptInWindow(body: RefObject<HTMLElement | null>, open: boolean) {
  useLayoutEffect(() => {
    const element = body.current;
    if (!open || !element) return;
    const place = () => {
      element.style.left = "";
      const { left, right } = element.getBoundingClientRect();
      const beyond = right - document.documentElement.clientWidth;
      if (beyond > 0) element.style.left = `${-Math.min(beyond, Math.max(left, 0))}px`;
    };
    place();
    const resized = typeof ResizeObserver === "undefined" ? null : new ResizeObserver(place);
    resized?.observe(element);
    window.addEventListener("resize", place);
    return () => {
      resized?.disconnect();
      window.removeEventListener("resize", place);
    };
  }, [body, open]);
}

/** Downloads of the saved draft in every format, plus an SVG drawing of the canvas. */
export function ExportMenu({ missionId, saved }: { missionId: string; saved: boolean }) {
  const svg = () => {
    const canvas = document.querySelector(".editor-canvas .react-flow__viewport");
    const edges = document.querySelector(".editor-canvas .react-flow__edges");
    if (!canvas) return;
    const text = canvasSvg(canvas as HTMLElement, edges as SVGElement | null);
    const url = URL.createObjectURL(new Blob([text], { type: "image/svg+xml" }));
    const a = document.createElement("a");
    a.href = url;
    a.download = `${missionId}.svg`;
    a.click();
    window.setTimeout(() => URL.revokeObjectURL(url), 1000);
  };
  return (
    <details className="export-menu">
      {/* One label whatever the save state: a summary that changed width re-wrapped the
          toolbar and moved the canvas under the pointer (see .save-state in styles.css). */}
      <summary>Export</summary>
      <ul>
        {!saved && <li className="hint">The last saved draft (saving…)</li>}
        {(["json", "avcl", "turtle", "dot", "plain"] as const).map((f) => (
          <li key={f}>
            <a href={exportHref(missionId, f)} download data-testid={`editor-export-${f}`}>
              {f === "json" ? "JSON" : f === "avcl" ? "AVCL" : f === "turtle" ? "Turtle" : f === "dot" ? "DOT" : "Plain text"}
            </a>
          </li>
        ))}
        <li>
          <button type="button" onClick={svg}>
            SVG of the canvas
          </button>
        </li>
      </ul>
    </details>
  );
}

/** An SVG document of the canvas: React Flow's edge layer plus a box and label per node. */
export function canvasSvg(viewport: HTMLElement, edges: SVGElement | null): string {
  const esc = (t: string) => t.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
  const boxes: string[] = [];
  let maxX = 0;
  let maxY = 0;
  viewport.querySelectorAll<HTMLElement>(".react-flow__node").forEach((n) => {
    const m = /translate\(([-\d.]+)px, ([-\d.]+)px\)/.exec(n.style.transform);
    const x = m ? Number(m[1]) : 0;
    const y = m ? Number(m[2]) : 0;
    const w = n.offsetWidth;
    const h = n.offsetHeight;
    maxX = Math.max(maxX, x + w);
    maxY = Math.max(maxY, y + h);
    boxes.push(
      `<g><rect x="${x}" y="${y}" width="${w}" height="${h}" rx="6" fill="#fff" stroke="#333"/>` +
        `<text x="${x + 8}" y="${y + 18}" font-family="sans-serif" font-size="12">${esc(n.innerText.split("\n").slice(0, 3).join(" · "))}</text></g>`,
    );
  });
  const edgeMarkup = edges ? edges.innerHTML : "";
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="-20 -20 ${maxX + 40} ${maxY + 40}">${edgeMarkup}${boxes.join("")}</svg>`;
}
