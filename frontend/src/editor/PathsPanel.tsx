/**
 * Paths explorer: counts per terminal (from the report), the saved draft's paths fetched page
 * by page with a progress bar and a cancel button, a virtualised list (only visible rows are
 * in the DOM), and the selected path highlighted on the graph with its Figure 6 trace.
 */
import { useEffect, useRef, useState } from "react";

import type { MissionPath, PathPage, Report } from "../api/client";
import { formatNumber } from "../format";
import { outcomeLetters, traceText } from "../trace";
import type { Orders, PathLike } from "./graph";

const PAGE = 500;
const ROW = 26;
const HEIGHT = 260;

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
  const [scroll, setScroll] = useState(0);
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
  const first = Math.max(0, Math.floor(scroll / ROW) - 5);
  const last = Math.min(paths.length, first + Math.ceil(HEIGHT / ROW) + 10);
  const selectedPath = chosen === null ? null : paths[chosen] ?? null;

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
            className="path-list"
            role="listbox"
            aria-label="Paths"
            tabIndex={0}
            style={{ height: HEIGHT, overflowY: "auto", position: "relative" }}
            onScroll={(e) => setScroll(e.currentTarget.scrollTop)}
            aria-activedescendant={chosen !== null ? `path-${chosen}` : undefined}
            onKeyDown={(e) => {
              if (e.key !== "ArrowDown" && e.key !== "ArrowUp") return;
              e.preventDefault();
              const next = Math.min(paths.length - 1, Math.max(0, (chosen ?? -1) + (e.key === "ArrowDown" ? 1 : -1)));
              setChosen(next);
              const p = paths[next]!;
              onHighlight(p, `path #${p.index}`);
              const top = next * ROW;
              const box = e.currentTarget;
              if (top < box.scrollTop) box.scrollTop = top;
              else if (top + ROW > box.scrollTop + HEIGHT) box.scrollTop = top + ROW - HEIGHT;
            }}
          >
            <div style={{ height: paths.length * ROW, position: "relative" }}>
              {paths.slice(first, last).map((p, k) => {
                const i = first + k;
                return (
                  <div
                    key={p.index}
                    id={`path-${i}`}
                    role="option"
                    aria-selected={i === chosen}
                    className={`path-row${i === chosen ? " active" : ""}`}
                    style={{ position: "absolute", top: i * ROW, height: ROW, left: 0, right: 0 }}
                    onClick={() => {
                      setChosen(i);
                      onHighlight(p, `path #${p.index}`);
                    }}
                  >
                    #{p.index} <code>{outcomeLetters(p.outcomes)}</code> → {p.terminal}
                  </div>
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
