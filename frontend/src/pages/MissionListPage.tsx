import { Link as RouteLink } from "@tanstack/react-router";
import { type FormEvent, useEffect, useState } from "react";

import type { MissionSummary } from "../api/client";
import { type MissionQuery, useMissionList } from "../api/missions";
import { type Column, DataTable } from "../components/DataTable";
import { Link } from "../components/Link";
import {
  currentCursor,
  firstPage,
  nextPage,
  Pager,
  previousPage,
} from "../components/Pager";
import { CheckBadge, ErrorMessage, Loading } from "../components/Status";
import { formatDateTime, statusLabel } from "../format";
import { replaceQuery } from "../navigation";
import { useCan } from "../session";

export const STATUSES = ["draft", "submitted", "approved", "rejected"] as const;
const PAGE_SIZE = 25;

const MISSION_COLUMNS: Column<MissionSummary>[] = [
  {
    header: "Mission",
    cell: (m) => (
      <>
        {/* A typed route link: the route's param name is checked when this is compiled. */}
        <RouteLink to="/missions/$missionId" params={{ missionId: m.id }}>
          {m.title || m.id}
        </RouteLink>
        <div className="sub">
          <code>{m.id}</code>
        </div>
      </>
    ),
  },
  {
    header: "Status",
    cell: (m) => (
      <>
        <span className={`status status-${m.status}`}>{statusLabel(m.status)}</span>
        {m.integrity && m.integrity.length > 0 ? (
          <div className="sub warning" role="alert" data-testid="status-integrity">
            {m.integrity.join("; ")}
          </div>
        ) : null}
      </>
    ),
  },
  { header: "Check", cell: (m) => <CheckBadge ok={m.ok} errors={m.errors} warnings={m.warnings} /> },
  { header: "Vehicle", cell: (m) => m.vehicle ?? "—" },
  { header: "Version", cell: (m) => (m.latest_version ? `v${m.latest_version}` : "—") },
  {
    header: "Updated",
    cell: (m) => (
      <>
        <time dateTime={m.updated_at}>{formatDateTime(m.updated_at)}</time>
        <div className="sub">by {m.updated_by}</div>
      </>
    ),
  },
];

export function MissionListPage({ search }: { search: string }) {
  const initial = new URLSearchParams(search);
  const [q, setQ] = useState(initial.get("q") ?? "");
  const [filters, setFilters] = useState({
    q: initial.get("q") ?? "",
    status: initial.get("status") ?? "",
  });
  const [pages, setPages] = useState(firstPage);
  const canImport = useCan("importMission");
  const cursor = currentCursor(pages);

  useEffect(() => {
    document.title = "Missions · Countersign";
  }, []);

  const query: MissionQuery = { limit: PAGE_SIZE };
  if (filters.q) query.q = filters.q;
  if (filters.status) query.status = filters.status;
  if (cursor) query.cursor = cursor;
  const { data, error, isFetching: loading } = useMissionList(query);

  const apply = (next: { q: string; status: string }) => {
    setFilters(next);
    setPages(firstPage());
    replaceQuery({ q: next.q, status: next.status });
  };

  const submit = (event: FormEvent) => {
    event.preventDefault();
    apply({ ...filters, q: q.trim() });
  };

  return (
    <section aria-labelledby="missions-title">
      <div className="page-head">
        <h1 id="missions-title" tabIndex={-1}>
          Missions
        </h1>
        {canImport && (
          <Link href="/import" className="button primary">
            Import or create mission
          </Link>
        )}
      </div>
      <form className="filters" role="search" aria-label="Filter missions" onSubmit={submit}>
        <label htmlFor="mission-q">Search</label>
        <input
          id="mission-q"
          type="search"
          placeholder="Title or id"
          value={q}
          onChange={(e) => setQ(e.target.value)}
        />
        <label htmlFor="mission-status">Status</label>
        <select
          id="mission-status"
          value={filters.status}
          onChange={(e) => apply({ q: q.trim(), status: e.target.value })}
        >
          <option value="">Any status</option>
          {STATUSES.map((s) => (
            <option key={s} value={s}>
              {statusLabel(s)}
            </option>
          ))}
        </select>
        <button type="submit">Search</button>
      </form>
      <ErrorMessage error={error} />
      {loading && !data ? (
        <Loading what="missions" />
      ) : data && data.items.length === 0 ? (
        <p className="empty">
          {filters.q || filters.status
            ? "No mission matches these filters."
            : canImport
              ? "No missions yet. Import orders (JSON, AVCL or Turtle) to start one."
              : "No missions yet."}
        </p>
      ) : data ? (
        <DataTable
          caption="Missions"
          className="missions"
          scroll
          busy={loading}
          columns={MISSION_COLUMNS}
          rows={data.items}
          rowKey={(m) => m.id}
        />
      ) : null}
      <Pager
        label="Mission pages"
        page={pages.cursors.length}
        hasPrevious={pages.cursors.length > 1}
        hasNext={!!data?.next_cursor}
        onPrevious={() => setPages(previousPage(pages))}
        onNext={() => data?.next_cursor && setPages(nextPage(pages, data.next_cursor))}
      />
    </section>
  );
}
