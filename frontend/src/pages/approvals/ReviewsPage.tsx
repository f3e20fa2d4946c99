/** Submissions waiting for a supervisor's decision (and recent decisions), newest first. */
import { useEffect } from "react";

import { api, unwrap } from "../../api/client";
import { Link } from "../../components/Link";
import { ErrorMessage, Loading } from "../../components/Status";
import { formatDateTime, shortDigest } from "../../format";
import { useLoad } from "../../useLoad";
import { reviewHref, type Submission } from "./api";
import { StateBadge } from "./parts";

export function ReviewsPage() {
  useEffect(() => {
    document.title = "Reviews · Countersign";
  }, []);
  const { data, error, loading } = useLoad(
    async () => unwrap(await api.GET("/api/submissions", { params: { query: { limit: 200 } } })),
    [],
  );
  const waiting = data?.filter((s) => s.state === "submitted") ?? [];
  const decided = data?.filter((s) => s.state !== "submitted").slice(0, 20) ?? [];
  const table = (rows: Submission[], caption: string) => (
    <table className="submissions">
      <caption className="visually-hidden">{caption}</caption>
      <thead>
        <tr>
          <th scope="col">Mission version</th>
          <th scope="col">State</th>
          <th scope="col">Submitted by</th>
          <th scope="col">Submitted</th>
          <th scope="col">Digest</th>
        </tr>
      </thead>
      <tbody>
        {rows.map((s) => (
          <tr key={s.id}>
            <td>
              <Link href={reviewHref(s.mission, s.version)}>
                Review {s.mission} v{s.version}
              </Link>
            </td>
            <td>
              <StateBadge state={s.state} />
            </td>
            <td>{s.submitted_by}</td>
            <td>
              <time dateTime={s.submitted_at}>{formatDateTime(s.submitted_at)}</time>
            </td>
            <td>
              <code title={s.digest}>{shortDigest(s.digest, 8)}</code>
            </td>
          </tr>
        ))}
      </tbody>
    </table>
  );
  return (
    <section aria-labelledby="reviews-title">
      <h1 id="reviews-title" tabIndex={-1}>
        Reviews
      </h1>
      <ErrorMessage error={error} />
      {loading && !data ? (
        <Loading what="the submissions" />
      ) : (
        <>
          <h2>Waiting for a decision</h2>
          {waiting.length ? table(waiting, "Submissions waiting for a decision") : <p className="empty">Nothing is waiting for review.</p>}
          {decided.length > 0 && (
            <>
              <h2>Recently decided or withdrawn</h2>
              {table(decided, "Recent submissions")}
            </>
          )}
        </>
      )}
    </section>
  );
}
