import { type FormEvent, useEffect, useRef, useState } from "react";

import { api, ApiError, type Session } from "../api/client";
import { ErrorMessage, Notice } from "../components/Status";

export function LoginPage({
  notice,
  onSignedIn,
}: {
  notice?: string | undefined;
  onSignedIn: (session: Session) => void;
}) {
  const [username, setUsername] = useState("");
  const [password, setPassword] = useState("");
  const [error, setError] = useState<string | null>(null);
  const [busy, setBusy] = useState(false);
  const userRef = useRef<HTMLInputElement>(null);

  useEffect(() => {
    userRef.current?.focus();
    document.title = "Sign in · Countersign";
  }, []);

  const submit = async (event: FormEvent) => {
    event.preventDefault();
    setBusy(true);
    setError(null);
    try {
      const { data, error: body, response } = await api.POST("/api/auth/login", {
        body: { username, password },
      });
      if (response.ok && data) {
        onSignedIn(data);
        return;
      }
      if (response.status === 401) {
        setError("Wrong username or password.");
      } else {
        setError(new ApiError(response.status, body).message);
      }
      setPassword("");
    } catch {
      setError("The server cannot be reached. Check that Countersign is running.");
    } finally {
      setBusy(false);
    }
  };

  return (
    <main className="centered" id="main">
      <form className="card login" onSubmit={submit} aria-labelledby="login-title">
        <h1 id="login-title">Sign in to Countersign</h1>
        {notice && <Notice>{notice}</Notice>}
        <label htmlFor="login-username">Username</label>
        <input
          id="login-username"
          ref={userRef}
          name="username"
          autoComplete="username"
          required
          value={username}
          onChange={(e) => setUsername(e.target.value)}
        />
        <label htmlFor="login-password">Password</label>
        <input
          id="login-password"
          name="password"
          type="password"
          autoComplete="current-password"
          required
          value={password}
          onChange={(e) => setPassword(e.target.value)}
        />
        <ErrorMessage error={error} />
        <button type="submit" className="primary" disabled={busy}>
          {busy ? "Signing in…" : "Sign in"}
        </button>
      </form>
    </main>
  );
}
