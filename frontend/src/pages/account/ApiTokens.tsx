import { type FormEvent, useState } from "react";

import type { components } from "../../api/schema";
import { useCreateToken, useRevokeToken, useTokens } from "../../api/tokens";
import { type Column, DataTable } from "../../components/DataTable";
import { ErrorMessage, Loading, Notice } from "../../components/Status";

type Scope = NonNullable<components["schemas"]["TokenIn"]["scopes"]>[number];
const SCOPES: Scope[] = ["read", "write", "decide"];

/** One's own API tokens: listed, created (the secret is shown once) and revoked. */
export function ApiTokens() {
  const tokens = useTokens();
  const createToken = useCreateToken();
  const revokeToken = useRevokeToken();
  const [name, setName] = useState("");
  const [scopes, setScopes] = useState<Scope[]>(["read"]);
  const [days, setDays] = useState(30);
  const [password, setPassword] = useState("");
  const [secret, setSecret] = useState<string | null>(null);
  const [error, setError] = useState<unknown>(null);
  const [notice, setNotice] = useState<string | null>(null);

  const create = async (event: FormEvent) => {
    event.preventDefault();
    setError(null);
    setNotice(null);
    try {
      // A token that can decide needs your password, entered again.
      const body = {
        name,
        scopes,
        expires_in_days: days,
        password: scopes.includes("decide") ? password : null,
      };
      const made = await createToken.mutateAsync(body);
      setSecret(made.token ?? null);
      setName("");
      setPassword("");
    } catch (e) {
      setError(e);
    }
  };

  const revoke = async (id: number, label: string) => {
    setError(null);
    setSecret(null);
    try {
      await revokeToken.mutateAsync(id);
      setNotice(`Token ${label} revoked.`);
    } catch (e) {
      setError(e);
    }
  };

  const rows = tokens.data ?? [];
  const columns: Column<(typeof rows)[number]>[] = [
    { header: "Name", cell: (t) => t.name },
    { header: "Scopes", cell: (t) => (t.scopes ?? []).join(", ") },
    { header: "Expires", cell: (t) => (t.expires_at ? new Date(t.expires_at).toLocaleDateString() : "never") },
    { header: "State", cell: (t) => (t.revoked ? "Revoked" : "Active") },
    {
      header: "Actions",
      cell: (t) =>
        !t.revoked && (
          <button type="button" onClick={() => void revoke(t.id, t.name)}>
            Revoke<span className="visually-hidden"> token {t.name}</span>
          </button>
        ),
    },
  ];
  return (
    <section className="card" aria-labelledby="tokens-title">
      <h2 id="tokens-title">API tokens</h2>
      <ErrorMessage error={tokens.error ?? error} />
      {notice && <Notice>{notice}</Notice>}
      {secret && (
        <Notice>
          New token (shown once, copy it now): <code data-testid="new-token">{secret}</code>
        </Notice>
      )}
      {tokens.isPending ? (
        <Loading what="tokens" />
      ) : rows.length === 0 ? (
        <p>You have no API tokens.</p>
      ) : (
        <DataTable
          caption="Your API tokens"
          className="tokens"
          columns={columns}
          rows={rows}
          rowKey={(t) => t.id}
          rowAttributes={() => ({ "data-testid": "token-row" })}
        />
      )}
      <form onSubmit={create} aria-label="Create an API token">
        <div className="grid">
          <label htmlFor="token-name">Token name</label>
          <input
            id="token-name"
            required
            maxLength={100}
            value={name}
            onChange={(e) => setName(e.target.value)}
          />
          <label htmlFor="token-days">Expires in days</label>
          <input
            id="token-days"
            type="number"
            min={1}
            max={366}
            value={days}
            onChange={(e) => setDays(Number(e.target.value))}
          />
        </div>
        <fieldset>
          <legend>Scopes</legend>
          {SCOPES.map((s) => (
            <label key={s}>
              <input
                type="checkbox"
                checked={scopes.includes(s)}
                onChange={(e) =>
                  setScopes(e.target.checked ? [...scopes, s] : scopes.filter((x) => x !== s))
                }
              />{" "}
              {s}
            </label>
          ))}
        </fieldset>
        {scopes.includes("decide") && (
          <div className="grid">
            <label htmlFor="token-password">Your password (for the decide scope)</label>
            <input
              id="token-password"
              type="password"
              required
              autoComplete="current-password"
              value={password}
              onChange={(e) => setPassword(e.target.value)}
            />
          </div>
        )}
        <button type="submit" disabled={scopes.length === 0}>
          Create token
        </button>
      </form>
    </section>
  );
}
