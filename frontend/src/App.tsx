import { RouterProvider } from "@tanstack/react-router";
import { useCallback, useEffect, useState } from "react";

import { useSignOut } from "./api/auth";
import { api, csrf, onUnauthorized, type Session } from "./api/client";
import { queryClient } from "./api/query";
import { ErrorMessage, Loading } from "./components/Status";
import { navigate } from "./navigation";
import { LoginPage } from "./pages/LoginPage";
import { createAppRouter } from "./routes";
import { SessionContext } from "./session";

type SessionState = { status: "checking" } | { status: "out"; notice?: string } | Session;

export function App() {
  const [session, setSession] = useState<SessionState>({ status: "checking" });
  const [startError, setStartError] = useState<unknown>(null);
  // One router for the page's life: it follows the browser's history across sign-ins.
  const [router] = useState(() => createAppRouter());

  const signedIn = useCallback((value: Session) => {
    csrf.set(value.csrf_token);
    setSession(value);
  }, []);

  useEffect(() => {
    onUnauthorized(() => {
      // What the last person's pages fetched is theirs: the next one to sign in starts empty.
      queryClient.clear();
      setSession({ status: "out", notice: "Your session has ended. Please sign in again." });
    });
    api.GET("/api/auth/me").then(
      ({ data, response }) => {
        if (response.ok && data) signedIn(data);
        else setSession({ status: "out" });
      },
      (error: unknown) => {
        setStartError(error);
        setSession({ status: "out" });
      },
    );
    return () => onUnauthorized(null);
  }, [signedIn]);

  const { mutateAsync: signOutOnServer } = useSignOut();
  const signOut = useCallback(async () => {
    try {
      await signOutOnServer();
    } finally {
      setSession({ status: "out", notice: "You have signed out." });
      navigate("/login", { replace: true });
    }
  }, [signOutOnServer]);

  if ("status" in session && session.status === "checking") {
    return (
      <main className="centered">
        <Loading what="Countersign" />
      </main>
    );
  }
  if ("status" in session) {
    // Signed out, any address shows the sign-in form; the address stays, to open after it
    // (the /login route itself goes on to the missions).
    return (
      <>
        <ErrorMessage error={startError} />
        <LoginPage notice={session.notice} onSignedIn={signedIn} />
      </>
    );
  }
  return (
    <SessionContext.Provider value={{ user: session.user, signOut }}>
      <RouterProvider router={router} />
    </SessionContext.Provider>
  );
}
