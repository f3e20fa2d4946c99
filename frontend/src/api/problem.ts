/**
 * Turns an error response into one sentence a person can act on. The API answers errors with
 * RFC 9457 problem documents (`application/problem+json`): `{type, title, status, detail}`,
 * and validation problems add `errors: [{path, message}]`.
 */

export interface ProblemError {
  path?: string;
  message?: string;
}

export interface Problem {
  type?: string;
  title?: string;
  status?: number;
  detail?: string;
  errors?: ProblemError[];
}

const FALLBACK: Record<number, string> = {
  400: "The request was not understood.",
  401: "You are not signed in, or your session has ended.",
  403: "Your role may not do this.",
  404: "Not found.",
  409: "This conflicts with the current state.",
  412: "Someone else saved first. Reload to see their changes; nothing was overwritten.",
  413: "The upload is too large.",
  415: "This file type is not supported.",
  422: "The input is not valid.",
  428: "The request must say which revision it edits.",
  429: "Too many attempts. Wait a moment and try again.",
};

function isProblem(body: unknown): body is Problem {
  return typeof body === "object" && body !== null && !Array.isArray(body);
}

export function problemMessage(body: unknown, status: number): string {
  if (typeof body === "string" && body.trim()) {
    return body.trim();
  }
  let text = "";
  if (isProblem(body)) {
    const title = typeof body.title === "string" ? body.title.trim() : "";
    const detail = typeof body.detail === "string" ? body.detail.trim() : "";
    text = title && detail && detail !== title ? `${title}: ${detail}` : detail || title;
    const errors = Array.isArray(body.errors) ? body.errors : [];
    const listed = errors
      .filter((e): e is ProblemError => typeof e === "object" && e !== null)
      .map((e) => [e.path, e.message].filter(Boolean).join(": "))
      .filter(Boolean);
    if (listed.length) {
      text = `${text || "The input is not valid"} (${listed.join("; ")})`;
    }
    // FastAPI's own validation errors, in case a route answers with them.
    const raw = (body as { detail?: unknown }).detail;
    if (!text && Array.isArray(raw)) {
      text = raw
        .map((d: { loc?: unknown[]; msg?: string }) =>
          [Array.isArray(d?.loc) ? d.loc.join(".") : "", d?.msg ?? ""].filter(Boolean).join(": "),
        )
        .filter(Boolean)
        .join("; ");
    }
  }
  return text || FALLBACK[status] || `The server answered ${status}.`;
}
