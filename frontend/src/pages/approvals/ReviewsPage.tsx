/** Submissions waiting for a supervisor's decision (and recent decisions), newest first. */
import { useEffect } from "react";

import { type Submission, useSubmissions } from "../../api/submissions";
import { type Column, DataTable } from "../../components/DataTable";
import { Link } from "../../components/Link";
import { ErrorMessage, Loading } from "../../components/Status";
import { formatDateTime, shortDigest } from "../../format";
import { reviewHref } from "./api";
import { StateBadge } from "./parts";

const SUBMISSION_COLUMNS: Column<Submission>[] = [
  {
    header: "Mission version",
    cell: (s) => (
      <Link href={reviewHref(s.mission, s.version)}>
        Review {s.mission} v{s.version}
      </Link>
    ),
  },
  { header: "State", cell: (s) => <StateBadge state={s.state} /> },
  { header: "Submitted by", cell: (s) => s.submitted_by },
  { header: "Submitted", cell: (s) => <time dateTime={s.submitted_at}>{formatDateTime(s.submitted_at)}</time> },
  { header: "Digest", cell: (s) => <code title={s.digest}>{shortDigest(s.digest, 8)}</code> },
];

export function ReviewsPage() {
  useEffect(() => {
    document.title = "Reviews · Countersign";
  }, []);
  const { data, error, isPending: loading } = useSubmissions(200);
  const waiting = data?.filter((s) => s.state === "submitted") ?? [];
  const decided = data?.filter((s) => s.state !== "submitted").slice(0, 20) ?? [];
  const table = (rows: Submission[], caption: string) => (
    <DataTable caption={caption} className="submissions" columns={SUBMISSION_COLUMNS} rows={rows} rowKey={(s) => s.id} />
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
