import { useCallback, useEffect, useRef, useState } from "react";

import { api, csrf, onUnauthorized, type Session } from "./api/client";
import { queryClient } from "./api/query";
import { Link } from "./components/Link";
import { ErrorMessage, Loading } from "./components/Status";
import { navigate, useLocationRoute } from "./navigation";
import { AccountPage } from "./pages/AccountPage";
import { EventsPage } from "./pages/EventsPage";
import { ImportPage } from "./pages/ImportPage";
import { LoginPage } from "./pages/LoginPage";
import { MissionListPage } from "./pages/MissionListPage";
import { MissionPage } from "./pages/MissionPage";
import { UsersPage } from "./pages/UsersPage";
import { VehiclesPage } from "./pages/vehicles/VehiclesPage";
import { ApprovalNavLinks, ApprovalPages } from "./pages/approvals";
import { can, ROLE_LABEL, type Role } from "./roles";
import type { Route } from "./router";
import { SessionContext, type SessionContextValue } from "./session";

type SessionState = { status: "checking" } | { status: "out"; notice?: string } | Session;

export function App() {
  const [session, setSession] = useState<SessionState>({ status: "checking" });
  const [startError, setStartError] = useState<unknown>(null);
  const { route, search } = useLocationRoute();

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

  const signOut = useCallback(async () => {
    try {
      await api.POST("/api/auth/logout");
    } finally {
      csrf.clear();
      queryClient.clear();
      setSession({ status: "out", notice: "You have signed out." });
      navigate("/login", { replace: true });
    }
  }, []);

  if ("status" in session && session.status === "checking") {
    return (
      <main className="centered">
        <Loading what="Countersign" />
      </main>
    );
  }
  if ("status" in session) {
    return (
      <>
        <ErrorMessage error={startError} />
        <LoginPage
          notice={session.notice}
          onSignedIn={(value) => {
            signedIn(value);
            if (route.name === "login") navigate("/missions", { replace: true });
          }}
        />
      </>
    );
  }
  return (
    <SessionContext.Provider value={{ user: session.user, signOut }}>
      <Shell route={route} search={search} session={{ user: session.user, signOut }} />
    </SessionContext.Provider>
  );
}

function Shell({
  route,
  search,
  session,
}: {
  route: Route;
  search: string;
  session: SessionContextValue;
}) {
  const { user, signOut } = session;
  const role = user.role as Role;
  const mainRef = useRef<HTMLElement>(null);
  const path =
    route.name === "mission"
      ? `mission:${route.id}`
      : route.name === "approvals"
        ? `approvals:${JSON.stringify(route.page)}`
        : route.name;

  useEffect(() => {
    // Move focus to the new page's heading so keyboard and screen reader users follow along.
    const heading = mainRef.current?.querySelector<HTMLElement>("h1");
    heading?.focus();
  }, [path]);

  useEffect(() => {
    if (route.name === "login") navigate("/missions", { replace: true });
  }, [route.name]);

  const current = (name: Route["name"]) =>
    route.name === name || (name === "missions" && route.name === "mission")
      ? ("page" as const)
      : undefined;

  return (
    <>
      <a className="skip-link" href="#main">
        Skip to content
      </a>
      <header className="app-header">
        <Link href="/missions" className="brand">
          Countersign
        </Link>
        <nav aria-label="Main">
          <ul>
            <li>
              <Link href="/missions" aria-current={current("missions")}>
                Missions
              </Link>
            </li>
            {can(role, "importMission") && (
              <li>
                <Link href="/import" aria-current={current("import")}>
                  Import
                </Link>
              </li>
            )}
            {can(role, "readEvents") && (
              <li>
                <Link href="/events" aria-current={current("events")}>
                  Activity
                </Link>
              </li>
            )}
            <ApprovalNavLinks role={role} current={route.name === "approvals" ? route.page : null} />
            {can(role, "manageUsers") && (
              <li>
                <Link href="/users" aria-current={current("users")}>
                  Users
                </Link>
              </li>
            )}
            {can(role, "manageVehicles") && (
              <li>
                <Link href="/vehicles" aria-current={current("vehicles")}>
                  Vehicles
                </Link>
              </li>
            )}
          </ul>
        </nav>
        <div className="whoami" aria-label="Signed-in user">
          <span>
            Signed in as <strong data-testid="current-user">{user.display_name || user.username}</strong>
          </span>
          <span className={`role role-${role}`} data-testid="current-role">
            {ROLE_LABEL[role] ?? user.role}
          </span>
          <Link href="/account" aria-current={current("account")}>
            Account
          </Link>
          <button type="button" onClick={() => void signOut()}>
            Sign out
          </button>
        </div>
      </header>
      <main id="main" ref={mainRef}>
        <Page route={route} search={search} role={role} />
      </main>
    </>
  );
}

function Page({ route, search, role }: { route: Route; search: string; role: Role }) {
  switch (route.name) {
    case "missions":
    case "login":
      return <MissionListPage search={search} />;
    case "mission":
      return <MissionPage key={route.id} id={route.id} tab={route.tab} />;
    case "import":
      return can(role, "importMission") ? <ImportPage /> : <Forbidden />;
    case "users":
      return can(role, "manageUsers") ? <UsersPage /> : <Forbidden />;
    case "vehicles":
      return can(role, "manageVehicles") ? <VehiclesPage /> : <Forbidden />;
    case "events":
      return can(role, "readEvents") ? <EventsPage /> : <Forbidden />;
    case "account":
      return <AccountPage />;
    case "approvals":
      return <ApprovalPages route={route.page} role={role} forbidden={<Forbidden />} />;
    case "notFound":
      return (
        <section>
          <h1 tabIndex={-1}>Page not found</h1>
          <p>
            There is no page at <code>{route.path}</code>. <Link href="/missions">Go to missions</Link>.
          </p>
        </section>
      );
  }
}

function Forbidden() {
  return (
    <section>
      <h1 tabIndex={-1}>Not available to your role</h1>
      <p>
        Your role may not use this page. <Link href="/missions">Go to missions</Link>.
      </p>
    </section>
  );
}
