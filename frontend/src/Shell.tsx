/** The signed-in frame around every page: header, main navigation, the page's outlet. */
import { Outlet, useRouterState } from "@tanstack/react-router";
import { useEffect, useRef } from "react";

import { Link } from "./components/Link";
import { ApprovalNavLinks } from "./pages/approvals";
import { can, ROLE_LABEL, type Role } from "./roles";
import { useSession } from "./session";

/** The main navigation entry a path belongs to (a mission's page is under Missions). */
export function section(pathname: string): string {
  const first = pathname.split("/")[1] ?? "";
  if (first === "" || first === "login") return "missions";
  if (/^\/missions\/[^/]+\/versions\//.test(pathname)) return "review";
  return first;
}

export function Shell() {
  const { user, signOut } = useSession();
  const role = user.role as Role;
  const mainRef = useRef<HTMLElement>(null);
  const pathname = useRouterState({ select: (s) => s.location.pathname });
  const at = section(pathname);

  useEffect(() => {
    // Move focus to the new page's heading so keyboard and screen reader users follow along.
    const heading = mainRef.current?.querySelector<HTMLElement>("h1");
    heading?.focus();
  }, [pathname]);

  const current = (name: string) => (at === name ? ("page" as const) : undefined);

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
            <ApprovalNavLinks role={role} current={at} />
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
        <Outlet />
      </main>
    </>
  );
}

export function NotFound() {
  const pathname = useRouterState({ select: (s) => s.location.pathname });
  return (
    <section>
      <h1 tabIndex={-1}>Page not found</h1>
      <p>
        There is no page at <code>{pathname}</code>. <Link href="/missions">Go to missions</Link>.
      </p>
    </section>
  );
}

export function Forbidden() {
  return (
    <section>
      <h1 tabIndex={-1}>Not available to your role</h1>
      <p>
        Your role may not use this page. <Link href="/missions">Go to missions</Link>.
      </p>
    </section>
  );
}
