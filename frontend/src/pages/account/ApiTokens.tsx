import { type FormEvent, useState } from "react";

import { api, ApiError, unwrap } from "../../api/client";
import type { components } from "../../api/schema";
import { ErrorMessage, Loading, Notice } from "../../components/Status";
import { useLoad } from "../../useLoad";

type Scope = NonNullable<components["schemas"]["TokenIn"]["scopes"]>[number];
const SCOPES: Scope[] = ["read", "write", "decide"];

/** One's own API tokens: listed, created (the secret is shown once) and revoked. */
export function ApiTokens({ version }: { version: number }) {
  const tokens = useLoad(async () => unwrap(await api.GET("/api/tokens")), [version]);
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
      const made = unwrap(await api.POST("/api/tokens", { body }));
      setSecret(made.token ?? null);
      setName("");
      setPassword("");
      tokens.reload();
    } catch (e) {
      setError(e);
    }
  };

  const revoke = async (id: number, label: string) => {
    setError(null);
    setSecret(null);
    const result = await api.DELETE("/api/tokens/{token_id}", {
      params: { path: { token_id: id } },
    });
    if (result.response.ok) {
      setNotice(`Token ${label} revoked.`);
      tokens.reload();
    } else {
      setError(new ApiError(result.response.status, result.error));
    }
  };

  const rows = tokens.data ?? [];
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
      {tokens.loading && !tokens.data ? (
        <Loading what="tokens" />
      ) : rows.length === 0 ? (
        <p>You have no API tokens.</p>
      ) : (
        <table className="tokens">
          <thead>
            <tr>
              <th scope="col">Name</th>
              <th scope="col">Scopes</th>
              <th scope="col">Expires</th>
              <th scope="col">State</th>
              <th scope="col">Actions</th>
            </tr>
          </thead>
          <tbody>
            {rows.map((t) => (
              <tr key={t.id} data-testid="token-row">
                <td>{t.name}</td>
                <td>{(t.scopes ?? []).join(", ")}</td>
                <td>{t.expires_at ? new Date(t.expires_at).toLocaleDateString() : "never"}</td>
                <td>{t.revoked ? "Revoked" : "Active"}</td>
                <td>
                  {!t.revoked && (
                    <button type="button" onClick={() => void revoke(t.id, t.name)}>
                      Revoke<span className="visually-hidden"> token {t.name}</span>
                    </button>
                  )}
                </td>
              </tr>
            ))}
          </tbody>
        </table>
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
