/**
 * A supervisor's signing keys: create a key pair in this browser (WebCrypto Ed25519, private
 * key non-extractable, kept in IndexedDB), register its public key with a fresh password
 * confirmation, rotate (new key, then the old one revoked) and revoke.
 */
import { type FormEvent, useEffect, useState } from "react";

import { useRegisterKey, useRevokeKey } from "../../api/keys";
import { type Column, DataTable } from "../../components/DataTable";
import { ErrorMessage, Loading, Notice } from "../../components/Status";
import { fingerprint } from "../../crypto/keystore";
import { formatDateTime } from "../../format";
import { useSession } from "../../session";
import type { Key } from "./api";
import { useSigningKeys } from "./signing";

function keyColumns(local: Set<string>, onRevoke: (key: Key) => void): Column<Key>[] {
  return [
    {
      header: "Fingerprint",
      cell: (k) => (
        <code title={`SHA-256 of the public key: ${k.key_id}`} data-testid="key-fingerprint">
          {fingerprint(k.key_id)}
        </code>
      ),
    },
    { header: "Name", cell: (k) => k.name },
    {
      header: "Status",
      cell: (k) => (
        <>
          <span className={`badge ${k.status === "active" ? "ok" : "muted"}`}>{k.status}</span>
          {k.revoked_at && ` ${formatDateTime(k.revoked_at)}`}
        </>
      ),
    },
    { header: "In this browser", cell: (k) => (local.has(k.key_id) ? "yes (can sign here)" : "no") },
    { header: "Registered", cell: (k) => <time dateTime={k.created_at}>{formatDateTime(k.created_at)}</time> },
    {
      header: "Actions",
      cell: (k) =>
        k.status === "active" && (
          <button type="button" onClick={() => onRevoke(k)} aria-label={`Revoke key ${fingerprint(k.key_id)}`}>
            Revoke
          </button>
        ),
    },
  ];
}

export function KeysPage() {
  const { user } = useSession();
  const keys = useSigningKeys(user.username);
  const [name, setName] = useState("");
  const [password, setPassword] = useState("");
  const registerKey = useRegisterKey(user.username);
  const busy = registerKey.isPending;
  const [error, setError] = useState<unknown>(null);
  const [notice, setNotice] = useState<string | null>(null);
  const [revoking, setRevoking] = useState<Key | null>(null);
  useEffect(() => {
    document.title = "Signing keys · Countersign";
  }, []);

  const mine = keys.server.filter((k) => k.user === user.username);
  const local = new Set(keys.local.map((k) => k.keyId));
  const active = mine.filter((k) => k.status === "active");

  const register = async (event: { preventDefault(): void }, rotate: boolean) => {
    event.preventDefault();
    setError(null);
    setNotice(null);
    try {
      if (!password) throw new Error("Confirm your password to register a key.");
      const revoked = rotate ? active : [];
      const registered = await registerKey.mutateAsync({ name: name || "browser", password, rotate: revoked });
      let text = `Key ${fingerprint(registered.key_id)} registered; its private key stays in this browser.`;
      if (revoked.length) text += ` Revoked ${revoked.map((k) => fingerprint(k.key_id)).join(", ")}.`;
      setNotice(text);
      setPassword("");
      setName("");
    } catch (e) {
      setError(e);
    }
  };

  return (
    <section aria-labelledby="keys-title">
      <h1 id="keys-title" tabIndex={-1}>
        Signing keys
      </h1>
      <p className="hint">
        You sign approvals with an Ed25519 key created in this browser. Its private key cannot be exported, not even by
        Countersign: it never leaves this browser profile. Only the public key is registered with the server. A key
        created in another browser (or with <code>countersign keygen</code>) signs there.
      </p>
      <form className="card" onSubmit={(e) => void register(e, active.length > 0)} aria-labelledby="new-key-title">
        <h2 id="new-key-title">{active.length ? "Rotate: new key, then revoke the old" : "Create and register a key"}</h2>
        <label htmlFor="key-name">Key name</label>
        <input id="key-name" value={name} maxLength={100} placeholder="e.g. office laptop" onChange={(e) => setName(e.target.value)} />
        <label htmlFor="key-password">Confirm your password</label>
        <input
          id="key-password"
          type="password"
          autoComplete="current-password"
          value={password}
          required
          onChange={(e) => setPassword(e.target.value)}
        />
        <div className="actions">
          <button type="submit" className="primary" disabled={busy}>
            {active.length ? "Rotate key" : "Create and register key"}
          </button>
          {active.length > 0 && (
            <button type="button" disabled={busy} onClick={(e) => void register(e, false)}>
              Add a key without revoking
            </button>
          )}
        </div>
      </form>
      <ErrorMessage error={error ?? keys.error} />
      {notice && <Notice>{notice}</Notice>}
      <h2>Your keys</h2>
      {keys.loading ? (
        <Loading what="your keys" />
      ) : mine.length === 0 ? (
        <p className="empty">You have no registered keys.</p>
      ) : (
        <DataTable caption="Your registered signing keys" className="keys" columns={keyColumns(local, setRevoking)} rows={mine} rowKey={(k) => k.key_id} />
      )}
      {revoking && (
        <RevokeKey
          keyRow={revoking}
          onDone={(text) => {
            setRevoking(null);
            if (text) setNotice(text);
          }}
        />
      )}
    </section>
  );
}

function RevokeKey({ keyRow, onDone }: { keyRow: Key; onDone: (notice: string | null) => void }) {
  const { user } = useSession();
  const [password, setPassword] = useState("");
  const [reason, setReason] = useState("");
  const revokeKey = useRevokeKey(user.username);
  const busy = revokeKey.isPending;
  const submit = (event: FormEvent) => {
    event.preventDefault();
    revokeKey.mutate(
      { keyId: keyRow.key_id, password, reason },
      { onSuccess: () => onDone(`Key ${fingerprint(keyRow.key_id)} revoked; earlier approvals keep verifying against it.`) },
    );
  };
  const error = revokeKey.error;
  return (
    <form className="card" onSubmit={(e) => void submit(e)} aria-labelledby="revoke-key-title">
      <h2 id="revoke-key-title">Revoke key {fingerprint(keyRow.key_id)}</h2>
      <label htmlFor="revoke-reason">Reason</label>
      <input id="revoke-reason" value={reason} maxLength={2000} onChange={(e) => setReason(e.target.value)} />
      <label htmlFor="revoke-password">Confirm your password</label>
      <input id="revoke-password" type="password" autoComplete="current-password" required value={password} onChange={(e) => setPassword(e.target.value)} />
      <ErrorMessage error={error} />
      <div className="actions">
        <button type="submit" className="danger" disabled={busy}>
          Revoke key
        </button>
        <button type="button" onClick={() => onDone(null)}>
          Cancel
        </button>
      </div>
    </form>
  );
}
