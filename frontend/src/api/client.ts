/**
 * The typed API client. Its types are generated from the backend's OpenAPI document
 * (`npm run generate-api`, see scripts/export-openapi), so a route or field that changes on the
 * server breaks the build here instead of a screen at run time.
 */
import createClient, { type Middleware } from "openapi-fetch";
import type { Readable } from "openapi-typescript-helpers";

import { applyCsrf, CsrfToken } from "./csrf";
import { problemMessage } from "./problem";
import type { components, paths } from "./schema";

export type { paths };

/** A response body as openapi-fetch hands it over (`Readable`: tuples read as arrays). */
/** A named schema of the OpenAPI document, as a response carries it. */
export type Schema<K extends keyof components["schemas"]> = Readable<components["schemas"][K]>;

type JsonBody<R> = R extends { content: { "application/json": infer T } } ? Readable<T> : never;

export type Session = JsonBody<paths["/api/auth/me"]["get"]["responses"][200]>;
export type User = Session["user"];
export type MissionPage = JsonBody<paths["/api/missions"]["get"]["responses"][200]>;
export type MissionSummary = MissionPage["items"][number];
export type MissionDetail = JsonBody<paths["/api/missions/{mission_id}"]["get"]["responses"][200]>;
export type Version = MissionDetail["versions"][number];
export type Report = JsonBody<paths["/api/missions/{mission_id}/report"]["get"]["responses"][200]>;
export type Finding = Report["findings"][number];
export type PathPage = JsonBody<paths["/api/missions/{mission_id}/paths"]["get"]["responses"][200]>;
export type MissionPath = PathPage["items"][number];
export type UserList = JsonBody<paths["/api/users"]["get"]["responses"][200]>;
export type EventList = JsonBody<paths["/api/events"]["get"]["responses"][200]>;
export type Event = EventList[number];

export const csrf = new CsrfToken();

let unauthorizedHandler: (() => void) | null = null;

/** Called when any request other than sign-in answers 401: the session has ended. */
export function onUnauthorized(handler: (() => void) | null): void {
  unauthorizedHandler = handler;
}

const sessionMiddleware: Middleware = {
  onRequest({ request }) {
    applyCsrf(request.method, request.headers, csrf.get());
    return request;
  },
  onResponse({ request, response }) {
    const path = new URL(request.url).pathname;
    if (response.status === 401 && !path.startsWith("/api/auth/")) {
      csrf.clear();
      unauthorizedHandler?.();
    }
    return response;
  },
};

export const api = createClient<paths>({
  baseUrl: typeof window === "undefined" ? "http://localhost" : window.location.origin,
  credentials: "same-origin",
});
api.use(sessionMiddleware);

/** An API error with a message fit to show (from the RFC 9457 problem document). */
export class ApiError extends Error {
  constructor(
    readonly status: number,
    readonly body: unknown,
  ) {
    super(problemMessage(body, status));
    this.name = "ApiError";
  }
}

/** Unwraps an openapi-fetch result: the data, or an ApiError that explains itself. */
export function unwrap<T>(result: { data?: T; error?: unknown; response: Response }): T {
  if (!result.response.ok || result.data === undefined) {
    throw new ApiError(result.response.status, result.error);
  }
  return result.data;
}

/** Where an export can be downloaded (a plain link: the cookie goes along, same origin). */
export function exportHref(missionId: string, format: ExportFormat): string {
  return `/api/missions/${encodeURIComponent(missionId)}/export?format=${format}`;
}

export type ExportFormat = "json" | "dot" | "plain" | "turtle" | "avcl";

export const EXPORT_FORMATS: { format: ExportFormat; label: string; description: string }[] = [
  { format: "json", label: "JSON", description: "orders in countersign.orders/1" },
  { format: "plain", label: "Plain text", description: "the plain-language orders" },
  { format: "dot", label: "DOT", description: "Graphviz graph of the goals" },
  { format: "turtle", label: "Turtle", description: "MEO ontology (RDF)" },
  { format: "avcl", label: "AVCL", description: "NPS AUV Workbench mission XML" },
];

/** Text of a route that answers a file (export, traces), with the same session handling. */
export async function fetchText(url: string): Promise<string> {
  const response = await fetch(url, { credentials: "same-origin", headers: { Accept: "*/*" } });
  const text = await response.text();
  if (!response.ok) {
    let body: unknown = text;
    try {
      body = JSON.parse(text);
    } catch {
      /* not JSON: keep the text */
    }
    if (response.status === 401) {
      csrf.clear();
      unauthorizedHandler?.();
    }
    throw new ApiError(response.status, body);
  }
  return text;
}
