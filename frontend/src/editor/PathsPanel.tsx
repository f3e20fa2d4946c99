/**
 * Paths explorer: counts per terminal (from the report), the saved draft's paths fetched page
 * by page with a progress bar and a cancel button, a virtualised list (only visible rows are
 * in the DOM) whose rows align each step in a column (goal id, title, outcome letter), the
 * path under the pointer highlighted on the graph, and the chosen one with its Figure 6 trace.
 */
import { useVirtualizer } from "@tanstack/react-virtual";
import { useEffect, useMemo, useRef, useState } from "react";

import type { MissionPath, PathPage, Report } from "../api/client";
import { PathGridHead, PathGridRow } from "../components/PathGrid";
import { formatNumber } from "../format";
import { gridWidth, titlesOf } from "../pathGrid";
import { traceText } from "../trace";
import type { Orders, PathLike } from "./graph";

const PAGE = 500;
const ROW = 27;
const HEIGHT = 280;

// Length: the path explorer's query form and its paged, virtualised grid.
export function PathsPanel({
  missionId,
  orders,
  report,
  revision,
  onHighlight,
}: {
  missionId: string;
  orders: Orders;
  report: Report | null;
  revision: number | null;
  onHighlight: (path: PathLike | null, label?: string) => void;
}) {
  const [paths, setPaths] = useState<MissionPath[]>([]);
  const [total, setTotal] = useState<number | null>(null);
  const [loading, setLoading] = useState(false);
  const [error, setError] = useState("");
  const [chosen, setChosen] = useState<number | null>(null);
  const [hovered, setHovered] = useState<number | null>(null);
  const listBox = useRef<HTMLDivElement>(null);
  const abort = useRef<AbortController | null>(null);

  const load = async () => {
    abort.current?.abort();
    const controller = new AbortController();
    abort.current = controller;
    setPaths([]);
    setChosen(null);
    setError("");
    setLoading(true);
    let cursor: string | null = null;
    const all: MissionPath[] = [];
    try {
      do {
        const url: string = `/api/missions/${encodeURIComponent(missionId)}/paths?limit=${PAGE}${cursor ? `&cursor=${encodeURIComponent(cursor)}` : ""}`;
        const response = await fetch(url, { credentials: "same-origin", signal: controller.signal });
        if (!response.ok) {
          setError(response.status === 409 ? "Fix the structural errors first: the paths cannot be counted." : `The paths could not be loaded (${response.status}).`);
          break;
        }
        const page = (await response.json()) as PathPage;
        all.push(...page.items);
        setTotal(page.count);
        setPaths([...all]);
        cursor = page.next_cursor;
      } while (cursor && !controller.signal.aborted);
    } catch (e) {
      if (!(e instanceof DOMException && e.name === "AbortError")) setError(String(e));
    } finally {
      setLoading(false);
    }
  };
  const cancel = () => abort.current?.abort();
  useEffect(() => () => abort.current?.abort(), []);
  // The list belongs to one saved revision; a new one starts over.
  useEffect(() => {
    abort.current?.abort();
    setPaths([]);
    setTotal(null);
    setChosen(null);
  }, [revision]);

  const counts = report?.paths;
  const selectedPath = chosen === null ? null : paths[chosen] ?? null;
  const titles = useMemo(() => titlesOf(orders as Parameters<typeof titlesOf>[0]), [orders]);
  const steps = useMemo(() => paths.reduce((n, p) => Math.max(n, p.goals.length), 1), [paths]);
  const rows = useVirtualizer({ count: paths.length, getScrollElement: () => listBox.current, estimateSize: () => ROW, overscan: 8 });
  const hover = (i: number | null) => {
    setHovered(i);
    const p = i === null ? selectedPath : paths[i];
    onHighlight(p ?? null, p ? `path #${p.index}` : undefined);
  };

  return (
    <section aria-labelledby="paths-title">
      <h3 id="paths-title">Paths</h3>
      {counts ? (
        <p data-testid="paths-counts">
          {formatNumber(counts.count)} paths:{" "}
          {Object.entries(counts.by_terminal)
            .map(([t, n]) => `${formatNumber(n)} to ${t}`)
            .join(", ")}
          .
        </p>
      ) : (
        <p className="empty">The paths cannot be counted until the structural errors are fixed.</p>
      )}
      <div className="actions">
        <button type="button" onClick={() => void load()} disabled={loading || !counts || revision === null}>
          {paths.length > 0 ? "Reload paths" : "List paths"}
        </button>
        {loading && (
          <button type="button" onClick={cancel}>
            Cancel
          </button>
        )}
        {revision === null && <span className="hint"> (waiting for the draft to save)</span>}
      </div>
      {(loading || (total !== null && paths.length < total)) && (
        <p>
          <progress max={total ?? 1} value={paths.length} aria-label="Paths loaded" /> {formatNumber(paths.length)} of{" "}
          {total === null ? "…" : formatNumber(total)}
          {!loading && " (cancelled)"}
        </p>
      )}
      {error && <p className="message error">{error}</p>}
      {paths.length > 0 && (
        <div className="paths-explorer">
          <div
            ref={listBox}
            className="path-list path-grid-scroll"
            role="listbox"
            aria-label="Paths"
            data-testid="editor-path-list"
            tabIndex={0}
            style={{ height: HEIGHT }}
            aria-activedescendant={chosen !== null ? `path-${chosen}` : undefined}
            onMouseLeave={() => hover(null)}
            onKeyDown={(e) => {
              if (e.key !== "ArrowDown" && e.key !== "ArrowUp") return;
              e.preventDefault();
              const next = Math.min(paths.length - 1, Math.max(0, (chosen ?? -1) + (e.key === "ArrowDown" ? 1 : -1)));
              setChosen(next);
              const p = paths[next]!;
              onHighlight(p, `path #${p.index}`);
              rows.scrollToIndex(next);
            }}
          >
            <PathGridHead steps={steps} />
            <div style={{ height: rows.getTotalSize(), width: gridWidth(steps), position: "relative" }}>
              {rows.getVirtualItems().map((row) => {
                const i = row.index;
                const p = paths[i]!;
                return (
                  <PathGridRow
                    key={p.index}
                    id={`path-${i}`}
                    role="option"
                    aria-selected={i === chosen}
                    path={p}
                    titles={titles}
                    steps={steps}
                    className={`${i === chosen ? "active" : ""}${i === hovered ? " hovered" : ""}`}
                    style={{ position: "absolute", top: row.start, height: ROW, left: 0, width: gridWidth(steps) }}
                    onMouseEnter={() => hover(i)}
                    onClick={() => {
                      setChosen(i);
                      onHighlight(p, `path #${p.index}`);
                    }}
                  />
                );
              })}
            </div>
          </div>
          {selectedPath && (
            <pre className="trace" data-testid="path-trace" aria-label={`Trace of path ${selectedPath.index}`}>
              {traceText(selectedPath, orders as Parameters<typeof traceText>[1])}
            </pre>
          )}
        </div>
      )}
    </section>
  );
}
