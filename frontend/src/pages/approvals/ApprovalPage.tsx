/**
 * One signed decision, as an auditor sees it: the orders as approved, plain-language orders,
 * findings, path summary and rehearsal record, and a verification run in this browser
 * (WebCrypto) of the signature, the key, the log and the checkpoint. Supervisors can revoke an
 * approval here with a signed reason.
 */
import { keepPreviousData, useQuery } from "@tanstack/react-query";
import { type FormEvent, useEffect, useState } from "react";

import { Link } from "../../components/Link";
import { ErrorMessage, Loading, Notice } from "../../components/Status";
import { fingerprint } from "../../crypto/keystore";
import { pinCheck } from "../../crypto/logkey";
import { type Check, verifyApproval } from "../../crypto/verify";
import { formatDateTime, shortDigest } from "../../format";
import { useSession } from "../../session";
import { approvalKeys, type Prepared, useApproval, useRevokeApproval } from "../../api/approvals";
import { titlesOf } from "../../pathGrid";
import { RehearsalSummary } from "./RehearsalSummary";
import { type ApprovalDetail, approvalHref, bundleHref, documentHref, loadEntries, loadMissionApprovals, reviewHref } from "./api";
import { LogKeyPanel, useLogKeyPin } from "./LogKeyPin";
import { OrdersGraph } from "./OrdersGraph";
import { FindingsTable, IntegrityWarning, PathSummaryTable, RulesSection, StateBadge } from "./parts";
import { ExecutionsSection } from "./Executions";
import { signPrepared, useSigningKeys } from "./signing";
import { historyCheck } from "./history";
import { ProfileDrift } from "../vehicles/ProfileDrift";

export function ApprovalPage({ id }: { id: number }) {
  const { data: record, error, isPending: loading } = useApproval(id);
  useEffect(() => {
    document.title = `Record ${id} · Countersign`;
  }, [id]);
  if (loading && !record) return <Loading what={`record ${id}`} />;
  if (!record) {
    return (
      <section>
        <h1 tabIndex={-1}>Record {id}</h1>
        <ErrorMessage error={error ?? "The record could not be loaded."} />
        <p>
          <Link href="/audit">Back to the audit history</Link>
        </p>
      </section>
    );
  }
  const predicate = record.statement.predicate ?? {};
  return (
    <section aria-labelledby="approval-title">
      <p className="breadcrumb">
        <Link href="/audit">Audit history</Link> / record {record.id}
      </p>
      <div className="page-head">
        <h1 id="approval-title" tabIndex={-1}>
          Record {record.id}: {record.mission} v{record.version}
        </h1>
        <StateBadge state={record.decision} />
      </div>
      <IntegrityWarning problems={record.integrity} />
      <ProfileDrift orders={record.orders} approved={record.decision === "approved"} />
      <dl className="facts">
        <div>
          <dt>Supervisor</dt>
          <dd>{record.supervisor}</dd>
        </div>
        <div>
          <dt>Operator (author)</dt>
          <dd>{record.operator}</dd>
        </div>
        <div>
          <dt>Vehicle</dt>
          <dd>{record.vehicle ?? "—"}</dd>
        </div>
        <div>
          <dt>Signed</dt>
          <dd>
            <time dateTime={String(predicate.time ?? record.created_at)}>{formatDateTime(String(predicate.time ?? record.created_at))}</time>
          </dd>
        </div>
        <div>
          <dt>Orders digest</dt>
          <dd>
            <code title={record.digest}>{shortDigest(record.digest)}</code>
          </dd>
        </div>
        <div>
          <dt>Key</dt>
          <dd>
            <code title={record.key.key_id}>{fingerprint(record.key.key_id)}</code> ({record.key.status})
          </dd>
        </div>
        <div>
          <dt>Log entry</dt>
          <dd>{record.log_index ?? "—"}</dd>
        </div>
        {record.reason && (
          <div>
            <dt>Reason</dt>
            <dd>{record.reason}</dd>
          </div>
        )}
        {record.revokes !== null && (
          <div>
            <dt>Revokes</dt>
            <dd>
              <Link href={approvalHref(record.revokes)}>record {record.revokes}</Link>
            </dd>
          </div>
        )}
      </dl>
      <p className="actions">
        <a href={bundleHref(record.mission)} download={`audit-bundle-${record.mission}.json`} className="button">
          Export bundle
        </a>
        <Link href={reviewHref(record.mission, record.version)}>Review page of v{record.version}</Link>
        <Link href={documentHref(record.mission, record.version)}>Printable approval document</Link>
      </p>
      <Verification record={record} />
      <Revoke record={record} />

      <h2>Orders as approved</h2>
      <OrdersGraph orders={record.orders} label={`Goal graph of ${record.mission} v${record.version}`} />
      <h3>Plain-language orders</h3>
      <pre className="orders-text" data-testid="approval-plain">
        {record.plain}
      </pre>
      <RulesSection rules={record.rules ?? []} headingLevel={3} />
      <details>
        <summary>Orders (JSON, as signed)</summary>
        <pre className="orders-text">{JSON.stringify(record.orders, null, 2)}</pre>
      </details>
      <h2>Findings</h2>
      <FindingsTable findings={record.findings} caption={`Findings of ${record.mission} v${record.version}`} />
      <h2>Path summary</h2>
      <PathSummaryTable paths={record.paths} />
      <h2>Rehearsal record</h2>
      <div data-testid="rehearsal">
        {record.rehearsal ? (
          <RehearsalSummary detail={record.rehearsal} titles={titlesOf(record.orders as Parameters<typeof titlesOf>[0])} />
        ) : (
          <p>None.</p>
        )}
      </div>
      <ExecutionsSection approvalId={record.id} />
      <details>
        <summary>Signed statement (in-toto) and envelope (DSSE)</summary>
        <pre className="orders-text">{JSON.stringify(record.statement, null, 2)}</pre>
        <pre className="orders-text">{record.envelope}</pre>
      </details>
    </section>
  );
}

function Verification({ record }: { record: ApprovalDetail }) {
  const [run, setRun] = useState(0);
  // Run in this browser on the record as fetched; "Check again" (run) runs it anew. Keyed by the
  // record itself, so a record that changed (revoked) is checked again; never retried on its own.
  const { data: logChecks, error, isFetching: loading } = useQuery({
    queryKey: [...approvalKeys.one(record.id), "verification", run, record],
    queryFn: async () => {
      // Up to the approval's own entry, so that its receipt is checked even if uncovered.
      const entries = await loadEntries(Math.max(record.checkpoint.size, (record.log_index ?? -1) + 1));
      // Every record of the mission too: a decision or revocation in the log must have one.
      const checks = await verifyApproval(record, entries, await loadMissionApprovals(record.mission));
      return [await historyCheck(record.checkpoint), ...checks];
    },
    retry: false,
    // The last run's checks stay shown while the next one runs.
    placeholderData: keepPreviousData,
  });
  const pin = useLogKeyPin(record.checkpoint.public_key);
  const pinned = pin.state ? pinCheck(pin.state) : null;
  // The pin comes first: every checkpoint check below is only as good as the key it used.
  const pinReady = pin.state !== undefined || Boolean(pin.error);
  const checks = logChecks && pinReady ? (pinned ? [pinned, ...logChecks] : logChecks) : undefined;
  const failed = checks?.filter((c) => !c.ok) ?? [];
  return (
    <section className="card verification" aria-labelledby="verification-title" aria-busy={loading}>
      <div className="page-head">
        <h2 id="verification-title">Verification in this browser</h2>
        <button
          type="button"
          onClick={() => {
            setRun((r) => r + 1);
            pin.reload();
          }}
          disabled={loading}
        >
          Verify again
        </button>
      </div>
      <p className="hint">
        Checked here with WebCrypto against the log entries, proof and checkpoint the server sent, and against the log key
        pinned in this browser; nothing is taken on the server's word. For a check without the server, export the bundle
        and run <code>countersign audit verify --log-key</code>.
      </p>
      <ErrorMessage error={error} />
      {loading && !checks ? (
        <Loading what="and checking the log" />
      ) : checks ? (
        <>
          <p
            className={failed.length ? "verdict bad" : pinned ? "verdict ok" : "verdict warn"}
            data-testid="verification-verdict"
            role="status"
          >
            {failed.length
              ? `${failed.length} of ${checks.length} checks failed: ${failed.map((c) => c.label).join(", ")}.`
              : !pinned
                ? `All ${checks.length} checks passed, against a log key not pinned in this browser: compare it with the published key and pin it below.`
                : `All ${checks.length} checks passed.`}
          </p>
          <ul className="checks">
            {checks.map((c: Check) => (
              <li key={c.id} className={c.ok ? "check-ok" : "check-bad"} data-testid={`check-${c.id}`}>
                <span aria-hidden="true">{c.ok ? "✓" : "✗"}</span> <strong>{c.label}</strong>:{" "}
                <span className="visually-hidden">{c.ok ? "passed" : "failed"}, </span>
                {c.detail}
              </li>
            ))}
          </ul>
        </>
      ) : null}
      <LogKeyPanel pin={pin} />
    </section>
  );
}

function Revoke({ record }: { record: ApprovalDetail }) {
  const { user } = useSession();
  if (user.role !== "supervisor" || record.decision !== "approved") return null;
  return <RevokeForm record={record} username={user.username} />;
}

// A revocation changes the records, the submissions and the mission: useRevokeApproval asks for them again.
function RevokeForm({ record, username }: { record: ApprovalDetail; username: string }) {
  const keys = useSigningKeys(username);
  const [reason, setReason] = useState("");
  const [password, setPassword] = useState(""); // checked by the server
  const revoke = useRevokeApproval(record.mission, record.id);
  const busy = revoke.isPending;
  const [error, setError] = useState<unknown>(null);
  const [done, setDone] = useState<number | null>(null);
  const key = keys.usable[0];
  const submit = async (event: FormEvent) => {
    event.preventDefault();
    if (!key) return;
    setError(null);
    try {
      if (!reason.trim()) throw new Error("A revocation needs a reason.");
      if (!password) throw new Error("Enter your password to sign: the server checks it with the revocation.");
      const sign = (prepared: Prepared) => signPrepared(prepared, key, { digest: record.digest, decision: "revoked" });
      const stored = await revoke.mutateAsync({ reason, keyId: key.keyId, password, sign });
      setDone(stored.id);
    } catch (e) {
      setError(e);
    }
  };
  return (
    <form className="card" onSubmit={(e) => void submit(e)} aria-labelledby="revoke-title">
      <h2 id="revoke-title">Revoke this approval</h2>
      <label htmlFor="revocation-reason">Reason (signed)</label>
      <textarea id="revocation-reason" rows={2} value={reason} maxLength={2000} onChange={(e) => setReason(e.target.value)} />
      <label htmlFor="revocation-password">Your password (checked by the server with this revocation)</label>
      <input id="revocation-password" type="password" autoComplete="current-password" required value={password} maxLength={1024} onChange={(e) => setPassword(e.target.value)} />
      <div className="actions">
        <button type="submit" className="danger" disabled={busy || !key} aria-describedby={!key ? "revoke-no-key" : undefined}>
          Sign revocation
        </button>
      </div>
      {!key && !keys.loading && (
        <p id="revoke-no-key" className="hint">
          You have no active signing key in this browser. <Link href="/keys">Create and register a key</Link>.
        </p>
      )}
      <ErrorMessage error={error ?? keys.error} />
      {done !== null && (
        <Notice>
          Revocation recorded as <Link href={approvalHref(done)}>record {done}</Link>.
        </Notice>
      )}
    </form>
  );
}
