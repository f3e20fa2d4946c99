import { type FormEvent, useEffect, useRef, useState } from "react";

import { useSignIn } from "../api/auth";
import { ApiError, type Session } from "../api/client";
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
  const signIn = useSignIn();
  const busy = signIn.isPending;
  const userRef = useRef<HTMLInputElement>(null);

  useEffect(() => {
    userRef.current?.focus();
    document.title = "Sign in · Countersign";
  }, []);

  const submit = async (event: FormEvent) => {
    event.preventDefault();
    setError(null);
    try {
      onSignedIn(await signIn.mutateAsync({ username, password }));
    } catch (e) {
      if (!(e instanceof ApiError)) {
        setError("The server cannot be reached. Check that Countersign is running.");
        return;
      }
      setError(e.status === 401 ? "Wrong username or password." : e.message);
      setPassword("");
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
