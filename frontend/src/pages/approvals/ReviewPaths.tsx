/**
 * The review's paths: every path of the version under review in a virtualised list (only the
 * rows in view are in the page), fetched from the paths API a page at a time (its cursor) as
 * the supervisor scrolls, searchable by a goal the path passes and by the terminal it ends at
 * (the server pages over the matches only). Rows align each step in a column (ReviewPathRow).
 */
import { useVirtualizer } from "@tanstack/react-virtual";
import { useEffect, useMemo, useRef, useState } from "react";

import { api, type MissionPath, type PathPage, unwrap } from "../../api/client";
import { ErrorMessage } from "../../components/Status";
import { CommitSelect, Picker } from "../../editor/fields";
import { type Choice, idAndTitle } from "../../editor/pickers";
import { formatNumber, plural } from "../../format";
import { titlesOf } from "../../pathGrid";
import { pathProbability } from "./probabilities";
import { ReviewPathHead, ReviewPathRow, rowWidth, stepWidth } from "./ReviewPathRow";

const PAGE = 200;
const ROW = 27;
const HEIGHT = 420;
/** Rows the list scrolls through at most (a browser cannot lay out an element of any height);
 * beyond it, searching narrows the list. */
export const MAX_ROWS = 200_000;

type Titled = { id: string; title?: string | null; kind?: string };
type Search = { goal: string; terminal: string };

export function ReviewPaths({ mission, version, orders, total }: { mission: string; version: number; orders: Record<string, unknown>; total: number }) {
  const [search, setSearch] = useState<Search>({ goal: "", terminal: "" });
  const goals = useMemo(() => (orders.goals as Titled[] | undefined) ?? [], [orders]);
  const terminals = useMemo(
    () => (orders.terminals as Titled[] | null | undefined) ?? [{ id: "COMPLETE", kind: "complete" }, { id: "ABORT", kind: "abort" }],
    [orders],
  );
  const titles = useMemo(() => titlesOf({ goals, terminals }), [goals, terminals]);
  const goalChoices: Choice[] = useMemo(
    () => [{ value: "", label: "any goal" }, ...goals.map((g) => ({ value: g.id, label: idAndTitle(g.id, g.title) }))],
    [goals],
  );
  const searching = search.goal !== "" || search.terminal !== "";
  return (
    <section aria-labelledby="review-paths-title" className="review-paths">
      <h3 id="review-paths-title">Every path</h3>
      <div className="path-search" role="search" aria-label="Search the paths">
        <Picker
          id="path-search-goal"
          label="Through goal"
          value={search.goal}
          choices={goalChoices}
          onCommit={(goal) => setSearch((s) => ({ ...s, goal }))}
        />
        <span>
          <label htmlFor="path-search-terminal">Ending at</label>
          <CommitSelect id="path-search-terminal" value={search.terminal} onCommit={(terminal) => setSearch((s) => ({ ...s, terminal }))}>
            <option value="">any terminal</option>
            {terminals.map((t) => (
              <option key={t.id} value={t.id}>
                {idAndTitle(t.id, t.title)}
              </option>
            ))}
          </CommitSelect>
        </span>
        {searching && (
          <button type="button" onClick={() => setSearch({ goal: "", terminal: "" })}>
            Show every path
          </button>
        )}
      </div>
      {/* A new search is a new list: it starts over from its first page. */}
      <PathRows key={`${mission}@${version}:${search.goal}|${search.terminal}`} mission={mission} version={version} search={search} titles={titles} total={total} />
    </section>
  );
}

function PathRows({
  mission,
  version,
  search,
  titles,
  total,
}: {
  mission: string;
  version: number;
  search: Search;
  titles: ReadonlyMap<string, string>;
  total: number;
}) {
  const [items, setItems] = useState<MissionPath[]>([]);
  const [matching, setMatching] = useState<number | null>(null);
  const [cursor, setCursor] = useState<string | null | undefined>(undefined); // undefined: not started
  const [error, setError] = useState<unknown>(null);
  const loading = useRef(false);
  const live = useRef(true);
  useEffect(() => {
    live.current = true;
    return () => {
      live.current = false;
    };
  }, []);
  const box = useRef<HTMLDivElement>(null);

  const loadMore = async () => {
    if (loading.current || cursor === null) return;
    loading.current = true;
    try {
      const query: { version: number; limit: number; cursor?: string; goal?: string; terminal?: string } = { version, limit: PAGE };
      if (cursor) query.cursor = cursor;
      if (search.goal) query.goal = search.goal;
      if (search.terminal) query.terminal = search.terminal;
      // The JSON page (the route also streams NDJSON and traces, hence the union type).
      const page = unwrap(await api.GET("/api/missions/{mission_id}/paths", { params: { path: { mission_id: mission }, query } })) as PathPage;
      if (!live.current) return; // the search changed meanwhile
      setItems((before) => [...before, ...page.items]);
      setMatching(page.matching ?? page.count);
      setCursor(page.next_cursor ?? null);
    } catch (e) {
      if (live.current) setError(e);
    } finally {
      loading.current = false;
    }
  };

  const known = matching ?? (search.goal || search.terminal ? 0 : total);
  const count = Math.min(known, MAX_ROWS);
  const steps = useMemo(() => items.reduce((n, p) => Math.max(n, p.goals.length), 1), [items]);
  // Sized by the goals' ids only (terminals have a column of their own).
  const step = useMemo(() => stepWidth(items.reduce((n, p) => Math.max(n, ...p.goals.map((g) => g.length)), 2)), [items]);
  const rows = useVirtualizer({ count, getScrollElement: () => box.current, estimateSize: () => ROW, overscan: 10 });
  const visible = rows.getVirtualItems();
  const lastShown = visible.length > 0 ? visible[visible.length - 1]!.index : 0;
  // Fetch the next page while the rows in view (and a little beyond) are not loaded yet.
  useEffect(() => {
    if (error || cursor === null) return;
    if (cursor === undefined || lastShown + 20 >= items.length) void loadMore();
    // loadMore reads the current cursor; re-run when it or the rows in view change.
  }, [cursor, lastShown, items.length, error]);

  const searching = search.goal !== "" || search.terminal !== "";
  return (
    <>
      <p className="hint" data-testid="review-paths-status" aria-live="polite">
        {matching === null
          ? "Loading the paths…"
          : searching
            ? `${plural(matching, "path")} of ${formatNumber(total)}${search.goal ? ` through ${search.goal}` : ""}${search.terminal ? ` ending at ${search.terminal}` : ""}`
            : `All ${plural(matching, "path")}`}
        {matching !== null && `; ${formatNumber(items.length)} loaded, more as you scroll`}
        {known > MAX_ROWS && `. The list scrolls through the first ${formatNumber(MAX_ROWS)}: search to narrow it`}. Outcomes: s succeed,
        f fail, c constraint violated.
      </p>
      <ErrorMessage error={error} />
      <div
        ref={box}
        className="review-paths-scroll"
        style={{ height: HEIGHT }}
        role="list"
        aria-label="Paths of this version"
        data-testid="review-paths"
        tabIndex={0}
      >
        <ReviewPathHead steps={steps} step={step} />
        <div style={{ height: rows.getTotalSize(), width: rowWidth(steps, step), position: "relative" }}>
          {visible.map((row) => {
            const p = items[row.index];
            const style = { position: "absolute" as const, top: row.start, height: ROW, left: 0 };
            if (!p) {
              return (
                <div key={`wait-${row.index}`} className="review-path-row" style={{ ...style, width: rowWidth(steps, step) }} role="listitem">
                  <span className="rp-cell hint">Loading…</span>
                </div>
              );
            }
            return (
              <ReviewPathRow key={p.index} path={p} titles={titles} steps={steps} step={step} style={style} chance={pathProbability(p.probability)} />
            );
          })}
        </div>
      </div>
    </>
  );
}
