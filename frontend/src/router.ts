/** A very small client-side router over the History API (FastAPI serves index.html for all). */
import { type ApprovalRoute, parseApprovalRoute } from "./pages/approvals/routes";

export type Route =
  | { name: "missions" }
  | { name: "mission"; id: string; tab: string }
  | { name: "import" }
  | { name: "users" }
  | { name: "account" }
  | { name: "vehicles" }
  | { name: "events" }
  | { name: "login" }
  | { name: "approvals"; page: ApprovalRoute }
  | { name: "notFound"; path: string };

export function parseRoute(pathname: string, search = ""): Route {
  const path = pathname.replace(/\/+$/, "") || "/";
  const params = new URLSearchParams(search);
  if (path === "/" || path === "/missions") return { name: "missions" };
  if (path === "/login") return { name: "login" };
  if (path === "/import") return { name: "import" };
  if (path === "/users") return { name: "users" };
  if (path === "/account") return { name: "account" };
  if (path === "/vehicles") return { name: "vehicles" };
  if (path === "/events") return { name: "events" };
  const mission = /^\/missions\/([^/]+)$/.exec(path);
  if (mission?.[1]) {
    let id: string;
    try {
      id = decodeURIComponent(mission[1]);
    } catch {
      return { name: "notFound", path };
    }
    return { name: "mission", id, tab: params.get("tab") ?? "orders" };
  }
  const approvals = parseApprovalRoute(path);
  if (approvals) return { name: "approvals", page: approvals };
  return { name: "notFound", path };
}

export function missionHref(id: string, tab?: string): string {
  const base = `/missions/${encodeURIComponent(id)}`;
  return tab && tab !== "orders" ? `${base}?tab=${encodeURIComponent(tab)}` : base;
}
