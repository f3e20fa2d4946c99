/**
 * The review of one version: what the supervisor approves (graph, plain-language orders,
 * findings, paths), what changed since the previously approved version, and the decision,
 * signed in this browser with the supervisor's non-extractable key.
 */
import { ProbabilityTable } from "./Probabilities";
import { useEffect, useMemo, useState } from "react";

import { Link } from "../../components/Link";
import { ErrorMessage, Loading, Notice } from "../../components/Status";
import { fingerprint } from "../../crypto/keystore";
import { formatDateTime, shortDigest } from "../../format";
import { titlesOf } from "../../pathGrid";
import { missionHref } from "../../router";
import { useSession } from "../../session";
import { type Prepared, useDecide } from "../../api/approvals";
import { useReview } from "../../api/versions";
import { approvalHref, type RecordedDecision, type Review } from "./api";
import { describeDiff, diffOrders } from "./diff";
import { MissionGraphs } from "./MissionGraphs";
import { ProfileDrift } from "../vehicles/ProfileDrift";
import { DiffView, FindingsTable, IntegrityWarning, PathSummaryTable, RulesSection, StateBadge } from "./parts";
import { ReviewPaths } from "./ReviewPaths";
import { ProcedureUsesSection } from "./ProcedureUses";
import { signPrepared, useSigningKeys } from "./signing";
import { ReceiptNote } from "./Receipt";
import { type CitedCampaigns, CitedEvidence, useCitedCampaigns } from "./CitedEvidence";

export function ReviewPage({ mission, version }: { mission: string; version: number }) {
  const { data: review, error, isPending: loading } = useReview(mission, version);
  const cited = useCitedCampaigns(review?.submissions[0]?.id);
  useEffect(() => {
    document.title = `Review ${mission} v${version} · Countersign`;
  }, [mission, version]);
  if (loading && !review) return <Loading what="the review" />;
  if (!review) {
    return (
      <section>
        <h1 tabIndex={-1}>
          Review of {mission} v{version}
        </h1>
        <ErrorMessage error={error ?? "The version could not be loaded."} />
      </section>
    );
  }
  const current = review.submissions[0];
  const title = typeof review.orders.title === "string" && review.orders.title ? review.orders.title : mission;
  return (
    <section aria-labelledby="review-title">
      <p className="breadcrumb">
        <Link href="/missions">Missions</Link> / <Link href={missionHref(mission, "versions")}>{mission}</Link> / v{version}
      </p>
      <h1 id="review-title" tabIndex={-1}>
        Review: {title} v{version}
      </h1>
      <IntegrityWarning problems={current?.integrity} />
      <ProfileDrift orders={review.orders} approved={current?.state === "approved"} />
      <dl className="facts">
        <div>
          <dt>State</dt>
          <dd>{current ? <StateBadge state={current.state} /> : <span className="badge muted">Not submitted</span>}</dd>
        </div>
        <div>
          <dt>Orders digest</dt>
          <dd>
            <code title={review.digest}>{shortDigest(review.digest)}</code>
          </dd>
        </div>
        <div>
          <dt>Author</dt>
          <dd>{review.author}</dd>
        </div>
        <div>
          <dt>Created</dt>
          <dd>
            <time dateTime={review.created_at}>{formatDateTime(review.created_at)}</time>
          </dd>
        </div>
        {current && (
          <div>
            <dt>Submitted</dt>
            <dd>
              by {current.submitted_by} on <time dateTime={current.submitted_at}>{formatDateTime(current.submitted_at)}</time>
            </dd>
          </div>
        )}
      </dl>
      <p className="hint">
        Read the changes, the graph, the orders, the contingency rules, the findings and the paths below; your decision
        is signed at the end.
      </p>

      <h2>Changes since the approved version</h2>
      <Changes review={review} />

      <h2>Goal graph</h2>
      <MissionGraphs orders={review.orders} label={`Goal graph of ${mission} v${version}`} findings={review.findings} />

      <h2>Plain-language orders</h2>
      <pre className="orders-text" data-testid="review-plain">
        {review.plain}
      </pre>

      <ProcedureUsesSection mission={mission} version={version} />

      <RulesSection rules={review.rules ?? []} />

      <h2>Findings</h2>
      <p className={review.ok ? "verdict ok" : "verdict bad"} data-testid="review-verdict">
        {review.ok ? "The orders pass every check." : "The orders do not pass."}
      </p>
      <FindingsTable findings={review.findings} caption={`Findings of ${mission} v${version}`} />

      <h2>Paths</h2>
      <PathSummaryTable paths={review.paths} />
      {review.paths && <ReviewPaths mission={mission} version={version} orders={review.orders} total={review.paths.count} />}
      {/* The report field is an open object in the API; its shape is verify/probability.py. */}
      <ProbabilityTable figures={review.probabilities} />

      <CitedEvidence rehearsal={current?.rehearsal} cited={cited} titles={titlesOf(review.orders as Parameters<typeof titlesOf>[0])} />

      <Decision mission={mission} review={review} cited={cited} />
    </section>
  );
}

function Changes({ review }: { review: Review }) {
  const role = useSession().user.role;
  const diff = useMemo(() => (review.previous ? diffOrders(review.previous.orders, review.orders) : null), [review]);
  if (!review.previous || !diff) {
    return (
      <p className="empty" data-testid="diff-summary">
        No earlier version of this mission was approved: all of these orders are new to review.
      </p>
    );
  }
  const lines = describeDiff(diff);
  return (
    <>
      <p data-testid="diff-summary">
        Compared with v{review.previous.version} (
        {role === "operator" ? (
          `approval ${review.previous.approval}`
        ) : (
          <Link href={approvalHref(review.previous.approval)}>approval {review.previous.approval}</Link>
        )}
        {review.previous.state === "revoked" ? ", since revoked" : ""}): {lines.length === 0 ? "no differences." : `${lines.length} difference${lines.length === 1 ? "" : "s"}.`}
      </p>
      <DiffView diff={diff} />
    </>
  );
}

function Decision({ mission, review, cited }: { mission: string; review: Review; cited: CitedCampaigns }) {
  const { user } = useSession();
  if (user.role !== "supervisor") return null;
  return <DecisionForm mission={mission} review={review} cited={cited} username={user.username} />;
}

// A decision changes the records, the submissions and this mission: useDecide asks for them again.
function DecisionForm({
  mission,
  review,
  cited,
  username,
}: {
  mission: string;
  review: Review;
  cited: CitedCampaigns;
  username: string;
}) {
  const keys = useSigningKeys(username);
  const [keyId, setKeyId] = useState("");
  const [reason, setReason] = useState("");
  // Fresh password for every decision: the server checks it, so a script that can use this
  // browser's key and session still cannot decide.
  const [password, setPassword] = useState("");
  const [error, setError] = useState<unknown>(null);
  const [result, setResult] = useState<RecordedDecision | null>(null);
  const submission = review.submissions[0];
  const recordDecision = useDecide(mission, submission?.id ?? 0);
  const busy = recordDecision.isPending;
  const selected = keys.usable.find((k) => k.keyId === keyId) ?? keys.usable[0];

  const decide = async (decision: "approved" | "rejected") => {
    if (!submission || !selected) return;
    setError(null);
    setResult(null);
    try {
      if (decision === "rejected" && !reason.trim()) throw new Error("A rejection needs a reason: say what must change.");
      if (!password) throw new Error("Enter your password to sign: the server checks it with your decision.");
      const sign = (prepared: Prepared) => {
        if (cited.loading || cited.error) throw new Error("The attached campaigns are not loaded: reload the review before signing.");
        return signPrepared(prepared, selected, {
          digest: review.digest,
          decision,
          submission: submission.id,
          rehearsal: submission.rehearsal ?? null,
          campaigns: cited.campaigns.map((c) => c.digest ?? ""),
          checker: review.checker,
          orders: review.orders,
        });
      };
      const stored = await recordDecision.mutateAsync({ decision, reason, keyId: selected.keyId, password, sign });
      setPassword("");
      setResult(stored);
    } catch (e) {
      setError(e);
    }
  };

  const refusal = review.decide_refusal ?? (!keys.loading && keys.usable.length === 0 ? "you have no active signing key in this browser" : null);
  return (
    <section className="card decision" aria-labelledby="decision-title">
      <h2 id="decision-title">Your decision</h2>
      {keys.loading ? (
        <Loading what="your signing keys" />
      ) : (
        <>
          {keys.usable.length > 0 && (
            <p>
              <label htmlFor="decision-key">Signing key</label>{" "}
              <select id="decision-key" value={selected?.keyId ?? ""} onChange={(e) => setKeyId(e.target.value)}>
                {keys.usable.map((k) => (
                  <option key={k.keyId} value={k.keyId}>
                    {k.name || "key"} · {fingerprint(k.keyId)}
                  </option>
                ))}
              </select>
            </p>
          )}
          <label htmlFor="decision-reason">Reason (required to reject)</label>
          <textarea id="decision-reason" rows={3} value={reason} onChange={(e) => setReason(e.target.value)} maxLength={2000} />
          <label htmlFor="decision-password">Your password (checked by the server with this decision)</label>
          <input
            id="decision-password"
            type="password"
            autoComplete="current-password"
            required
            value={password}
            onChange={(e) => setPassword(e.target.value)}
            maxLength={1024}
          />
          <div className="actions">
            <button
              type="button"
              className="primary"
              disabled={busy || refusal !== null}
              aria-describedby={refusal ? "decision-refusal" : undefined}
              onClick={() => void decide("approved")}
            >
              Sign approval
            </button>
            <button
              type="button"
              className="danger"
              disabled={busy || refusal !== null}
              aria-describedby={refusal ? "decision-refusal" : undefined}
              onClick={() => void decide("rejected")}
            >
              Sign rejection
            </button>
            {busy && <span role="status">Signing in this browser…</span>}
          </div>
        </>
      )}
      <ErrorMessage error={error ?? keys.error} />
      {result && (
        <Notice>
          <span data-testid="decision-verdict">
            The server verified your signature and recorded {result.decision === "approved" ? "the approval" : "the rejection"} (
            {result.decision} #{result.id}
            {result.log_index !== null ? `, log entry ${result.log_index}` : ""}).
          </span>{" "}
          <Link href={approvalHref(result.id)}>Open the record</Link>
          <ReceiptNote receipt={result.receipt} />
        </Notice>
      )}
      {/* After a decision the refusal ("submission 1 is approved") is its consequence, so it
          comes below the decision's own message, in the order things happened. */}
      {!keys.loading && (
        <>
          {refusal && (
            <p id="decision-refusal" className="hint" data-testid="decision-refusal">
              You cannot decide: {refusal}.
              {keys.usable.length === 0 && !review.decide_refusal && (
                <>
                  {" "}
                  <Link href="/keys">Create and register a key</Link>.
                </>
              )}
            </p>
          )}
        </>
      )}
    </section>
  );
}
