/**
 * The submission's rehearsal record: which record the submission cites, and for
 * its operator, the mission's stored records to attach. Only a record of exactly this version's
 * orders (same digest) can be attached; the others are listed with why not, and the server
 * refuses them all the same.
 */
import { useState } from "react";

import type { Schema } from "../../api/client";
import { type StoredRecord, useRehearsalRecords } from "../../api/rehearsals";
import { useAttachRehearsal } from "../../api/submissions";
import { type Column, DataTable } from "../../components/DataTable";
import { ErrorMessage } from "../../components/Status";
import { formatDateTime, shortDigest } from "../../format";

type Submission = Schema<"SubmissionOut">;


/** A stored record a row: which, of which orders, by whom and when, and its Attach button. */
function recordColumns(submission: Submission, version: number, busy: boolean, attach: (digest: string) => void): Column<StoredRecord>[] {
  const what = (r: StoredRecord) => (r.version !== null ? `v${r.version}` : r.source);
  return [
    { header: "Record", cell: (r) => <code>{shortDigest(r.digest, 12)}</code> },
    {
      header: "Rehearsed",
      cell: (r) => (
        <>
          {what(r)}
          {r.orders_digest !== submission.digest && (
            <span className="hint"> — other orders ({shortDigest(r.orders_digest, 8)}), not v{version}</span>
          )}
        </>
      ),
    },
    {
      header: "By, when",
      cell: (r) => (
        <>
          {r.owner ?? "?"}, <time dateTime={String(r.created_at)}>{formatDateTime(String(r.created_at))}</time>
        </>
      ),
    },
    {
      header: "Attach",
      hiddenHeader: true,
      cell: (r) => {
        const cited = r.digest === submission.rehearsal;
        return (
          <button
            type="button"
            disabled={busy || cited}
            // The visible word starts the name (WCAG 2.5.3, axe label-content-name-mismatch).
            aria-label={`${cited ? "Attached" : "Attach"} record ${shortDigest(r.digest, 12)} (${what(r)})`}
            title={r.orders_digest === submission.digest ? undefined : `The record rehearsed other orders than v${version}; the server will refuse it.`}
            onClick={() => attach(r.digest)}
          >
            {cited ? "Attached" : "Attach"}
          </button>
        );
      },
    },
  ];
}

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
          <DataTable
            caption={`Rehearsal records of ${mission}`}
            showCaption
            className="records-table"
            rows={records}
            rowKey={(r) => r.digest}
            rowAttributes={() => ({ "data-testid": "rehearsal-record-row" })}
            columns={recordColumns(submission, version, busy, (digest) => void attach(digest))}
          />
        )
      )}
      <ErrorMessage error={error ?? loadError} />
    </div>
  );
}
