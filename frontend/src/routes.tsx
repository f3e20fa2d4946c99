/**
 * Every address of the signed-in app, as one TanStack Router tree: typed params, a not-found
 * page for the rest, and the forbidden page where a role may not use a page (the server refuses
 * the same calls; the pages only spare the user a page of refusals). FastAPI serves index.html
 * for every path outside /api, so each of these addresses can be opened or reloaded directly.
 */
import {
  createRootRoute,
  createRoute,
  createRouter,
  Navigate,
  notFound,
  type ParsedLocation,
  type RouterHistory,
  useRouterState,
} from "@tanstack/react-router";
import type { ReactNode } from "react";

import { appHistory } from "./navigation";
import { AccountPage } from "./pages/AccountPage";
import { EventsPage } from "./pages/EventsPage";
import { ImportPage } from "./pages/ImportPage";
import { MissionListPage } from "./pages/MissionListPage";
import { MissionPage } from "./pages/MissionPage";
import { UsersPage } from "./pages/UsersPage";
import { ApprovalPage } from "./pages/approvals/ApprovalPage";
import { AuditPage } from "./pages/approvals/AuditPage";
import { DocumentPage } from "./pages/approvals/DocumentPage";
import { KeysPage } from "./pages/approvals/KeysPage";
import { ReviewPage } from "./pages/approvals/ReviewPage";
import { ReviewsPage } from "./pages/approvals/ReviewsPage";
import { PAGE_ROLES } from "./pages/approvals/routes";
import { VehiclesPage } from "./pages/vehicles/VehiclesPage";
import { type Action, can } from "./roles";
import { useSession } from "./session";
import { Forbidden, NotFound, Shell } from "./Shell";

/** A record or version number in an address: 1 to 10 digits, no leading zero; else no page. */
export function positive(raw: string): number {
  if (!/^[1-9][0-9]{0,9}$/.test(raw)) throw notFound();
  return Number(raw);
}

/** A mission's version in an address, as a number. */
const versioned = {
  parse: (raw: { missionId: string; version: string }) => ({ missionId: raw.missionId, version: positive(raw.version) }),
  stringify: (value: { missionId: string; version: number }) => ({ missionId: value.missionId, version: String(value.version) }),
};

/** The page if the signed-in role may `action`, else the forbidden page. */
function Allowed({ action, children }: { action: Action; children: ReactNode }) {
  return can(useSession().user.role, action) ? <>{children}</> : <Forbidden />;
}

/** The same for the approval pages, whose roles are listed beside them. */
function ApprovalAllowed({ page, children }: { page: keyof typeof PAGE_ROLES; children: ReactNode }) {
  return PAGE_ROLES[page].includes(useSession().user.role) ? <>{children}</> : <Forbidden />;
}

/** The list reads its filters from the query string itself (q, status; not JSON-typed). */
function MissionList() {
  const search = useRouterState({ select: (s) => s.location.searchStr });
  return <MissionListPage search={search} />;
}

const rootRoute = createRootRoute({ component: Shell, notFoundComponent: NotFound });

const indexRoute = createRoute({ getParentRoute: () => rootRoute, path: "/", component: MissionList });

const missionsRoute = createRoute({ getParentRoute: () => rootRoute, path: "/missions", component: MissionList });

/** Signed in already: the sign-in address goes on to the missions. */
const loginRoute = createRoute({
  getParentRoute: () => rootRoute,
  path: "/login",
  component: () => <Navigate to="/missions" replace />,
});

const missionRoute = createRoute({
  getParentRoute: () => rootRoute,
  path: "/missions/$missionId",
  validateSearch: (search: Record<string, unknown>): { tab?: string } =>
    search.tab === undefined ? {} : { tab: String(search.tab) },
  component: function Mission() {
    const { missionId } = missionRoute.useParams();
    const { tab } = missionRoute.useSearch();
    return <MissionPage key={missionId} id={missionId} tab={tab ?? "orders"} />;
  },
});

const reviewRoute = createRoute({
  getParentRoute: () => rootRoute,
  path: "/missions/$missionId/versions/$version/review",
  params: versioned,
  component: function Review() {
    const { missionId, version } = reviewRoute.useParams();
    return (
      <ApprovalAllowed page="review">
        <ReviewPage key={`${missionId}/${version}`} mission={missionId} version={version} />
      </ApprovalAllowed>
    );
  },
});

const documentRoute = createRoute({
  getParentRoute: () => rootRoute,
  path: "/missions/$missionId/versions/$version/document",
  params: versioned,
  component: function Document() {
    const { missionId, version } = documentRoute.useParams();
    return (
      <ApprovalAllowed page="document">
        <DocumentPage key={`${missionId}/${version}`} mission={missionId} version={version} />
      </ApprovalAllowed>
    );
  },
});

const approvalRoute = createRoute({
  getParentRoute: () => rootRoute,
  path: "/audit/$approvalId",
  params: {
    parse: (raw: { approvalId: string }) => ({ approvalId: positive(raw.approvalId) }),
    stringify: (value: { approvalId: number }) => ({ approvalId: String(value.approvalId) }),
  },
  component: function Approval() {
    const { approvalId } = approvalRoute.useParams();
    return (
      <ApprovalAllowed page="approval">
        <ApprovalPage key={approvalId} id={approvalId} />
      </ApprovalAllowed>
    );
  },
});

/** A page with no params (its role check, if any, is in `page`). */
function plain<P extends string>(path: P, page: () => ReactNode) {
  return createRoute({ getParentRoute: () => rootRoute, path, component: page });
}

const routeTree = rootRoute.addChildren([
  indexRoute,
  missionsRoute,
  loginRoute,
  missionRoute,
  reviewRoute,
  documentRoute,
  approvalRoute,
  plain("/audit", () => <ApprovalAllowed page="audit"><AuditPage /></ApprovalAllowed>),
  plain("/reviews", () => <ApprovalAllowed page="reviews"><ReviewsPage /></ApprovalAllowed>),
  plain("/keys", () => <ApprovalAllowed page="keys"><KeysPage /></ApprovalAllowed>),
  plain("/import", () => <Allowed action="importMission"><ImportPage /></Allowed>),
  plain("/users", () => <Allowed action="manageUsers"><UsersPage /></Allowed>),
  plain("/vehicles", () => <Allowed action="manageVehicles"><VehiclesPage /></Allowed>),
  plain("/events", () => <Allowed action="readEvents"><EventsPage /></Allowed>),
  plain("/account", () => <AccountPage />),
]);

/** Whether the router should place the window after a navigation: only when it went to another
 * page (back and forward return to where that page was left, others start at the top). A change
 * of the query string alone (a list's filter, a mission's tab) keeps the window where the reader
 * scrolled it; the router would otherwise scroll to the top after every navigation. */
function placesWindow(): (options: { location: ParsedLocation }) => boolean {
  let shown: string | undefined;
  return ({ location }) => {
    const otherPage = location.pathname !== shown;
    shown = location.pathname;
    return otherPage;
  };
}

export function createAppRouter(history: RouterHistory = appHistory()) {
  // Pages fetch through TanStack Query themselves: the router only picks the page.
  return createRouter({ routeTree, history, trailingSlash: "never", scrollRestoration: placesWindow() });
}

export type AppRouter = ReturnType<typeof createAppRouter>;

declare module "@tanstack/react-router" {
  interface Register {
    router: AppRouter;
  }
}
