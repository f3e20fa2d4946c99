/**
 * The mission page's submission panel (Versions tab): pick a version, see its state, submit it
 * for review (operators; the button says why when it cannot be submitted) or withdraw it.
 */
import { useEffect, useState } from "react";

import { RehearsalCitation } from "./RehearsalCitation";
import { CampaignCitation } from "../campaigns/CampaignCitation";
import { Link } from "../../components/Link";
import { ErrorMessage, Loading, Notice } from "../../components/Status";
import { formatDateTime } from "../../format";
import { useSession } from "../../session";
import { documentHref, reviewHref } from "./api";
import { useSubmission } from "../../api/submissions";
import { useReview } from "../../api/versions";
import { IntegrityWarning, StateBadge } from "./parts";

/** A submission or withdrawal invalidates the mission (api/submissions.ts): its page follows. */
export function SubmissionPanel({ mission, versions }: { mission: string; versions: number[] }) {
  const { user } = useSession();
  const newest = versions.length ? Math.max(...versions) : null;
  const [chosen, setChosen] = useState<number | null>(newest);
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<unknown>(null);
  const [done, setDone] = useState<string | null>(null);
  useEffect(() => setChosen(newest), [newest]);
  const { data: review, error: loadError, isFetching: loading } = useReview(mission, chosen);
  const submission = useSubmission(mission);
  // A campaign or rehearsal attached (its mutation asked for the review again): say so.
  const attached = (message: string) => setDone(message);
  if (newest === null || chosen === null) {
    return (
      <section aria-labelledby="submission-title" className="card">
        <h3 id="submission-title">Submission for review</h3>
        <p className="empty">Create a version first: supervisors review and approve versions, not the draft.</p>
      </section>
    );
  }
  const current = review?.submissions[0];
  const act = async (what: "submit" | "withdraw") => {
    setBusy(true);
    setError(null);
    setDone(null);
    try {
      if (what === "submit") {
        await submission.mutateAsync({ submit: chosen });
        setDone(`Version ${chosen} submitted for review.`);
      } else if (current) {
        await submission.mutateAsync({ withdraw: current.id });
        setDone(`Submission ${current.id} withdrawn.`);
      }
    } catch (e) {
      setError(e);
    } finally {
      setBusy(false);
    }
  };
  const isOperator = user.role === "operator";
  const mayWithdraw = isOperator && current?.state === "submitted" && current.submitted_by === user.username;
  return (
    <section aria-labelledby="submission-title" className="card submission-panel">
      <h3 id="submission-title">Submission for review</h3>
      <label htmlFor="submission-version">Version</label>{" "}
      <select id="submission-version" value={chosen} onChange={(e) => setChosen(Number(e.target.value))}>
        {[...versions].sort((a, b) => b - a).map((n) => (
          <option key={n} value={n}>
            v{n}
          </option>
        ))}
      </select>
      {loading && !review ? (
        <Loading what="the version's state" />
      ) : review ? (
        <>
          <p>
            State: {current ? <StateBadge state={current.state} /> : <span className="badge muted">Not submitted</span>}
            {current && (
              <>
                {" "}
                — submission {current.id} by {current.submitted_by} on{" "}
                <time dateTime={current.submitted_at}>{formatDateTime(current.submitted_at)}</time>
                {current.decided_by && ` · ${current.state} by ${current.decided_by}`}
                {current.reason && ` · reason: ${current.reason}`}
              </>
            )}
          </p>
          {/* The state above is the log's; a submissions row that says otherwise is named. */}
          <IntegrityWarning problems={current?.integrity} />
        </>
      ) : null}
      {/* Shown while the state loads too (Submit disabled): what is below does not move under
          a pointer when the state arrives. */}
      {(review || loading) && (
        <div className="actions">
          {isOperator && (
            <button
              type="button"
              className="primary"
              disabled={busy || !review?.may_submit}
              aria-describedby={review?.submit_refusal ? "submit-refusal" : undefined}
              onClick={() => void act("submit")}
            >
              Submit version {chosen}
            </button>
          )}
          {mayWithdraw && (
            <button type="button" disabled={busy} onClick={() => void act("withdraw")}>
              Withdraw submission
            </button>
          )}
          <Link href={reviewHref(mission, chosen)}>Open the review of v{chosen}</Link>
          <Link href={documentHref(mission, chosen)}>Printable approval document of v{chosen}</Link>
        </div>
      )}
      {review && (
        <>
          {current && (
            <CampaignCitation
              mission={mission}
              version={chosen}
              submission={current}
              mayAttach={mayWithdraw}
              onAttached={attached}
            />
          )}
          {current && (
            <RehearsalCitation
              mission={mission}
              version={chosen}
              submission={current}
              mayAttach={mayWithdraw}
              onAttached={attached}
            />
          )}
          {isOperator && review.submit_refusal && (
            <p id="submit-refusal" className="hint" data-testid="submit-refusal">
              Cannot submit: {review.submit_refusal}.
            </p>
          )}
        </>
      )}
      <ErrorMessage error={error ?? loadError} />
      {done && <Notice>{done}</Notice>}
    </section>
  );
}
