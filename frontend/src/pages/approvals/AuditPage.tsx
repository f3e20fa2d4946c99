/** The approval history: filters (mission, operator, supervisor, vehicle, decision, dates),
 * newest first, page by page; each record opens its audit page. */
import { type FormEvent, useEffect, useState } from "react";

import { type ApprovalQuery, useApprovalHistory } from "../../api/approvals";
import { type Column, DataTable } from "../../components/DataTable";
import { Link } from "../../components/Link";
import { currentCursor, firstPage, nextPage, Pager, previousPage } from "../../components/Pager";
import { ErrorMessage, Loading } from "../../components/Status";
import { formatDateTime, shortDigest } from "../../format";
import { replaceQuery } from "../../navigation";
import { approvalHref, type ApprovalSummary, bundleHref } from "./api";
import { StateBadge } from "./parts";

const PAGE = 25;
const FIELDS = ["mission", "operator", "supervisor", "vehicle", "decision", "since", "until"] as const;
type Filters = Record<(typeof FIELDS)[number], string>;
const EMPTY: Filters = { mission: "", operator: "", supervisor: "", vehicle: "", decision: "", since: "", until: "" };

function fromSearch(): Filters {
  const params = new URLSearchParams(window.location.search);
  return Object.fromEntries(FIELDS.map((f) => [f, params.get(f) ?? ""])) as Filters;
}

/** A date input's day as the start of that day in the browser's time zone (ISO 8601). */
function dayStart(day: string, plusDays = 0): string | undefined {
  if (!day) return undefined;
  const date = new Date(`${day}T00:00:00`);
  if (Number.isNaN(date.getTime())) return undefined;
  date.setDate(date.getDate() + plusDays);
  return date.toISOString();
}

const HISTORY_COLUMNS: Column<ApprovalSummary>[] = [
  { header: "Record", cell: (a) => <Link href={approvalHref(a.id)}>Record {a.id}</Link> },
  {
    header: "Mission",
    cell: (a) => (
      <>
        {a.mission} v{a.version} <code title={a.digest}>{shortDigest(a.digest, 8)}</code>
      </>
    ),
  },
  {
    header: "Decision",
    cell: (a) => (
      <>
        <StateBadge state={a.decision} />
        {a.revokes !== null && ` (of record ${a.revokes})`}
      </>
    ),
  },
  { header: "Operator", cell: (a) => a.operator },
  { header: "Supervisor", cell: (a) => a.supervisor },
  { header: "Vehicle", cell: (a) => a.vehicle ?? "—" },
  { header: "Signed", cell: (a) => <time dateTime={a.created_at}>{formatDateTime(a.created_at)}</time> },
  { header: "Log entry", cell: (a) => a.log_index ?? "—" },
];

export function AuditPage() {
  const [filters, setFilters] = useState<Filters>(fromSearch);
  const [form, setForm] = useState<Filters>(filters);
  const [pages, setPages] = useState(firstPage);
  const cursor = currentCursor(pages);
  useEffect(() => {
    document.title = "Audit history · Countersign";
  }, []);
  const query: Record<string, string | number> = { limit: PAGE };
  for (const f of ["mission", "operator", "supervisor", "vehicle", "decision"] as const) if (filters[f]) query[f] = filters[f];
  const since = dayStart(filters.since);
  const until = dayStart(filters.until, 1);
  if (since) query.since = since;
  if (until) query.until = until;
  if (cursor) query.cursor = Number(cursor);
  const { data, error, isFetching: loading } = useApprovalHistory(query as ApprovalQuery);

  const apply = (event: FormEvent) => {
    event.preventDefault();
    setFilters(form);
    setPages(firstPage());
    replaceQuery(Object.fromEntries(FIELDS.map((f) => [f, form[f]])));
  };
  const input = (field: keyof Filters, label: string, type = "text") => (
    <div>
      <label htmlFor={`filter-${field}`}>{label}</label>
      <input id={`filter-${field}`} type={type} value={form[field]} onChange={(e) => setForm({ ...form, [field]: e.target.value })} />
    </div>
  );

  return (
    <section aria-labelledby="audit-title">
      <h1 id="audit-title" tabIndex={-1}>
        Audit history
      </h1>
      <p className="hint">
        Every signed decision, newest first. Open one to verify its signature and its place in the log in this browser, or
        export a bundle for <code>countersign audit verify</code> (offline).{" "}
        <a href={bundleHref(filters.mission || undefined)} download={`audit-bundle${filters.mission ? `-${filters.mission}` : ""}.json`}>
          Export bundle{filters.mission ? ` of ${filters.mission}` : ""}
        </a>
      </p>
      <form className="card filters" onSubmit={apply} aria-label="Filter the history">
        <div className="grid">
          {input("mission", "Mission")}
          {input("operator", "Operator")}
          {input("supervisor", "Supervisor")}
          {input("vehicle", "Vehicle")}
          <div>
            <label htmlFor="filter-decision">Decision</label>
            <select id="filter-decision" value={form.decision} onChange={(e) => setForm({ ...form, decision: e.target.value })}>
              <option value="">Any</option>
              <option value="approved">Approved</option>
              <option value="rejected">Rejected</option>
              <option value="revoked">Revoked</option>
            </select>
          </div>
          {input("since", "From (date)", "date")}
          {input("until", "To (date)", "date")}
        </div>
        <div className="actions">
          <button type="submit" className="primary">
            Apply filters
          </button>
          <button
            type="button"
            onClick={() => {
              setForm(EMPTY);
              setFilters(EMPTY);
              setPages(firstPage());
              replaceQuery(Object.fromEntries(FIELDS.map((f) => [f, null])));
            }}
          >
            Clear
          </button>
        </div>
      </form>
      <ErrorMessage error={error} />
      {loading && !data ? (
        <Loading what="the history" />
      ) : data && data.items.length === 0 ? (
        <p className="empty">No signed decisions match.</p>
      ) : data ? (
        <DataTable
          caption="Signed decisions, newest first"
          className="approvals"
          scroll
          busy={loading}
          columns={HISTORY_COLUMNS}
          rows={data.items}
          rowKey={(a) => a.id}
        />
      ) : null}
      {data && (
        <Pager
          label="History pages"
          page={pages.cursors.length}
          hasPrevious={pages.cursors.length > 1}
          hasNext={data.next_cursor !== null}
          onPrevious={() => setPages(previousPage(pages))}
          onNext={() => data.next_cursor !== null && setPages(nextPage(pages, String(data.next_cursor)))}
        />
      )}
    </section>
  );
}
