import { useEffect, useState } from "react";

import { api, unwrap } from "../api/client";
import { Link } from "../components/Link";
import { Pager } from "../components/Pager";
import { ErrorMessage, Loading } from "../components/Status";
import { formatDateTime, shortDigest } from "../format";
import { missionHref } from "../router";
import { useLoad } from "../useLoad";

const PAGE_SIZE = 50;

/** The append-only event log, oldest first (the API pages with `after`: the last id seen). */
export function EventsPage() {
  const [afters, setAfters] = useState<number[]>([0]);
  const after = afters[afters.length - 1] ?? 0;
  const { data, error, loading } = useLoad(
    async () =>
      unwrap(await api.GET("/api/events", { params: { query: { after, limit: PAGE_SIZE } } })),
    [after],
  );

  useEffect(() => {
    document.title = "Activity · Countersign";
  }, []);

  const last = data?.[data.length - 1];
  return (
    <section aria-labelledby="events-title">
      <h1 id="events-title" tabIndex={-1}>
        Activity log
      </h1>
      <p className="hint">Every state change, in order. Entries are never edited or removed.</p>
      <ErrorMessage error={error} />
      {loading && !data ? (
        <Loading what="the log" />
      ) : data && data.length === 0 ? (
        <p className="empty">No events{afters.length > 1 ? " after these" : ""}.</p>
      ) : data ? (
        <div className="table-wrap">
          <table className="events">
            <caption className="visually-hidden">Event log entries</caption>
            <thead>
              <tr>
                <th scope="col">#</th>
                <th scope="col">When</th>
                <th scope="col">Who</th>
                <th scope="col">What</th>
                <th scope="col">Mission</th>
                <th scope="col">Digest before → after</th>
              </tr>
            </thead>
            <tbody>
              {data.map((e) => (
                <tr key={e.id}>
                  <td>{e.id}</td>
                  <td>
                    <time dateTime={e.at}>{formatDateTime(e.at)}</time>
                  </td>
                  <td>{e.actor ?? "system"}</td>
                  <td>
                    <code>{e.kind}</code>
                    {e.integrity && e.integrity.length > 0 ? (
                      <ul className="integrity warning" role="alert" data-testid="event-integrity">
                        {e.integrity.map((problem) => (
                          <li key={problem}>Not as logged: {problem}</li>
                        ))}
                      </ul>
                    ) : null}
                  </td>
                  <td>{e.mission ? <Link href={missionHref(e.mission)}>{e.mission}</Link> : "—"}</td>
                  <td>
                    {e.before_digest || e.after_digest ? (
                      <code>
                        {shortDigest(e.before_digest, 8) || "∅"} → {shortDigest(e.after_digest, 8) || "∅"}
                      </code>
                    ) : (
                      "—"
                    )}
                  </td>
                </tr>
              ))}
            </tbody>
          </table>
        </div>
      ) : null}
      <Pager
        label="Log pages"
        page={afters.length}
        hasPrevious={afters.length > 1}
        hasNext={!!data && data.length === PAGE_SIZE && !!last}
        onPrevious={() => setAfters(afters.slice(0, -1))}
        onNext={() => last && setAfters([...afters, last.id])}
      />
    </section>
  );
}
