/**
 * The submission's rehearsal record: which record the submission cites, and for
 * its operator, the mission's stored records to attach. Only a record of exactly this version's
 * orders (same digest) can be attached; the others are listed with why not, and the server
 * refuses them all the same.
 */
import { useState } from "react";

import type { Schema } from "../../api/client";
import { useRehearsalRecords } from "../../api/rehearsals";
import { useAttachRehearsal } from "../../api/submissions";
import { ErrorMessage } from "../../components/Status";
import { formatDateTime, shortDigest } from "../../format";

type Submission = Schema<"SubmissionOut">;

export function RehearsalCitation({
  mission,
  version,
  submission,
  mayAttach,
  onAttached,
}: {
  mission: string;
  version: number;
  submission: Submission;
  /** The submitting operator, while the submission awaits a decision. */
  mayAttach: boolean;
  onAttached: (message: string) => void;
}) {
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<unknown>(null);
  const listed = useRehearsalRecords(mission, 50, mayAttach);
  const records = mayAttach ? listed.data : [];
  const loadError = listed.error;
  const attachRecord = useAttachRehearsal(mission, submission.id);
  const attach = async (digest: string) => {
    setBusy(true);
    setError(null);
    try {
      await attachRecord.mutateAsync(digest);
      onAttached(`Rehearsal record ${shortDigest(digest, 12)} attached to submission ${submission.id}.`);
    } catch (e) {
      setError(e);
    } finally {
      setBusy(false);
    }
  };
  return (
    <div className="rehearsal-citation" data-testid="rehearsal-citation">
      <p data-testid="cited-rehearsal">
        Rehearsal record:{" "}
        {submission.rehearsal ? (
          <a href={`/api/rehearsal-records/${submission.rehearsal}/replay.html`} target="_blank" rel="noreferrer">
            <code>{shortDigest(submission.rehearsal, 16)}</code>
          </a>
        ) : (
          "none attached"
        )}
      </p>
      {mayAttach && records && (
        records.length === 0 ? (
          <p className="hint">No rehearsal recorded for this mission yet: rehearse v{version} (Rehearse tab), then attach its record here.</p>
        ) : (
          <table className="records-table">
            <caption>Rehearsal records of {mission}</caption>
            <thead>
              <tr>
                <th scope="col">Record</th>
                <th scope="col">Rehearsed</th>
                <th scope="col">By, when</th>
                <th scope="col">
                  <span className="visually-hidden">Attach</span>
                </th>
              </tr>
            </thead>
            <tbody>
              {records.map((r) => {
                const same = r.orders_digest === submission.digest;
                const cited = r.digest === submission.rehearsal;
                const what = r.version !== null ? `v${r.version}` : r.source;
                return (
                  <tr key={r.digest} data-testid="rehearsal-record-row">
                    <td>
                      <code>{shortDigest(r.digest, 12)}</code>
                    </td>
                    <td>
                      {what}
                      {!same && (
                        <span className="hint"> — other orders ({shortDigest(r.orders_digest, 8)}), not v{version}</span>
                      )}
                    </td>
                    <td>
                      {r.owner ?? "?"}, <time dateTime={String(r.created_at)}>{formatDateTime(String(r.created_at))}</time>
                    </td>
                    <td>
                      <button
                        type="button"
                        disabled={busy || cited}
                        // The visible word starts the name (WCAG 2.5.3, axe label-content-name-mismatch).
                        aria-label={`${cited ? "Attached" : "Attach"} record ${shortDigest(r.digest, 12)} (${what})`}
                        title={same ? undefined : `The record rehearsed other orders than v${version}; the server will refuse it.`}
                        onClick={() => void attach(r.digest)}
                      >
                        {cited ? "Attached" : "Attach"}
                      </button>
                    </td>
                  </tr>
                );
              })}
            </tbody>
          </table>
        )
      )}
      <ErrorMessage error={error ?? loadError} />
    </div>
  );
}
