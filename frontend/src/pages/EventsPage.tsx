import { type FormEvent, useEffect, useState } from "react";

import type { Event } from "../api/client";
import { useEvents } from "../api/events";
import { type Column, DataTable } from "../components/DataTable";
import { Link } from "../components/Link";
import { Pager } from "../components/Pager";
import { ErrorMessage, Loading } from "../components/Status";
import { formatDateTime, shortDigest } from "../format";
import { missionHref } from "../router";

const PAGE_SIZE = 50;

/** Event families and kinds offered by the kind filter (a family matches all its kinds). */
const KINDS = [
  "user", "user.created", "user.updated", "user.password_changed", "mission", "draft",
  "version", "submission", "approval", "approval.approved", "approval.rejected",
  "approval.revoked", "rehearsal", "key", "token", "vehicle", "chart", "execution", "log",
];

interface Filters {
  kind: string;
  actor: string;
  target: string;
  since: string;
  until: string;
}

const NO_FILTERS: Filters = { kind: "", actor: "", target: "", since: "", until: "" };

/** A `datetime-local` value (the browser's zone) as an ISO instant, or undefined. */
function instant(local: string): string | undefined {
  if (!local) return undefined;
  const when = new Date(local);
  return Number.isNaN(when.getTime()) ? undefined : when.toISOString();
}

const EVENT_COLUMNS: Column<Event>[] = [
  { header: "#", cell: (e) => e.index ?? "—" },
  { header: "When", cell: (e) => <time dateTime={e.at}>{formatDateTime(e.at)}</time> },
  { header: "Who", cell: (e) => e.actor ?? "system" },
  {
    header: "What",
    cell: (e) => (
      <>
        <code>{e.kind}</code>
        {e.integrity && e.integrity.length > 0 ? (
          <ul className="integrity warning" role="alert" data-testid="event-integrity">
            {e.integrity.map((problem) => (
              <li key={problem}>Not as logged: {problem}</li>
            ))}
          </ul>
        ) : null}
      </>
    ),
  },
  {
    header: "Target",
    testId: "event-target",
    cell: (e) =>
      e.target && e.mission && e.target.startsWith(`mission ${e.mission}`) ? (
        <Link href={missionHref(e.mission)}>{e.target}</Link>
      ) : (
        (e.target ?? "—")
      ),
  },
  { header: "Change", testId: "event-change", cell: (e) => e.change },
  {
    header: "Digest before → after",
    cell: (e) =>
      e.before_digest || e.after_digest ? (
        <code>
          {shortDigest(e.before_digest, 8) || "∅"} → {shortDigest(e.after_digest, 8) || "∅"}
        </code>
      ) : (
        "—"
      ),
  },
];

/**
 * The append-only event log, newest first, numbered by each event's index in the transparency
 * log; filtered and paged by the server (`before`: the last id seen).
 */
export function EventsPage() {
  const [draft, setDraft] = useState<Filters>(NO_FILTERS);
  const [filters, setFilters] = useState<Filters>(NO_FILTERS);
  const [befores, setBefores] = useState<(number | undefined)[]>([undefined]);
  const before = befores[befores.length - 1];
  const { data, error, isFetching: loading } = useEvents({
    order: "newest",
    before,
    limit: PAGE_SIZE,
    kind: filters.kind || undefined,
    actor: filters.actor || undefined,
    target: filters.target || undefined,
    since: instant(filters.since),
    until: instant(filters.until),
  });

  useEffect(() => {
    document.title = "Activity · Countersign";
  }, []);

  const apply = (next: Filters) => {
    setFilters(next);
    setBefores([undefined]);
  };
  const submit = (e: FormEvent) => {
    e.preventDefault();
    apply({ ...draft, actor: draft.actor.trim(), target: draft.target.trim() });
  };
  const field = (name: keyof Filters) => ({
    value: draft[name],
    onChange: (e: { target: { value: string } }) => setDraft({ ...draft, [name]: e.target.value }),
  });
  const filtered = Object.values(filters).some(Boolean);
  const last = data?.[data.length - 1];
  return (
    <section aria-labelledby="events-title">
      <h1 id="events-title" tabIndex={-1}>
        Activity log
      </h1>
      <p className="hint">
        Every state change, newest first. # is the event's entry in the transparency log. Entries are never edited
        or removed.
      </p>
      <form className="filters" role="search" aria-label="Filter the log" onSubmit={submit}>
        <label htmlFor="events-kind">Kind</label>
        <select id="events-kind" {...field("kind")}>
          <option value="">Any kind</option>
          {KINDS.map((k) => (
            <option key={k} value={k}>
              {k.includes(".") ? k : `${k}.*`}
            </option>
          ))}
        </select>
        <label htmlFor="events-actor">Who</label>
        <input id="events-actor" placeholder="username or system" maxLength={64} {...field("actor")} />
        <label htmlFor="events-target">Target</label>
        <input id="events-target" type="search" placeholder="user, mission, key…" maxLength={200} {...field("target")} />
        <label htmlFor="events-since">From</label>
        <input id="events-since" type="datetime-local" {...field("since")} />
        <label htmlFor="events-until">Until</label>
        <input id="events-until" type="datetime-local" {...field("until")} />
        <button type="submit">Filter</button>
        {filtered && (
          <button
            type="button"
            onClick={() => {
              setDraft(NO_FILTERS);
              apply(NO_FILTERS);
            }}
          >
            Clear filters
          </button>
        )}
      </form>
      <ErrorMessage error={error} />
      {loading && !data ? (
        <Loading what="the log" />
      ) : data && data.length === 0 ? (
        <p className="empty">
          No events{filtered ? " match these filters" : ""}
          {befores.length > 1 ? " before these" : ""}.
        </p>
      ) : data ? (
        <DataTable
          caption="Event log entries, newest first"
          className="events"
          scroll
          busy={loading}
          columns={EVENT_COLUMNS}
          rows={data}
          rowKey={(e) => e.id}
          rowAttributes={(e) => ({ "data-testid": "event-row", "data-index": String(e.index ?? "") })}
        />
      ) : null}
      <Pager
        label="Log pages"
        page={befores.length}
        hasPrevious={befores.length > 1}
        hasNext={!!data && data.length === PAGE_SIZE && !!last}
        onPrevious={() => setBefores(befores.slice(0, -1))}
        onNext={() => last && setBefores([...befores, last.id])}
      />
    </section>
  );
}
