import { describe, expect, it } from "vitest";

import { api, csrf } from "./client";
import { applyCsrf, CSRF_HEADER, isStateChanging } from "./csrf";
import { problemMessage } from "./problem";

/** Sends the request through the real client and hands back what reached "the network". */
async function capture(call: (fetch: (r: Request) => Promise<Response>) => Promise<unknown>) {
  const seen: Request[] = [];
  await call(async (request) => {
    seen.push(request);
    return new Response(JSON.stringify({}), {
      status: 200,
      headers: { "Content-Type": "application/json" },
    });
  });
  const request = seen[0];
  if (!request) throw new Error("no request was sent");
  return request;
}

describe("CSRF header", () => {
  it("goes only on state-changing methods", () => {
    expect(["POST", "put", "PATCH", "DELETE"].every(isStateChanging)).toBe(true);
    expect(["GET", "head", "OPTIONS"].some(isStateChanging)).toBe(false);
  });

  it("is set for a POST and removed from a GET", () => {
    const post = new Headers();
    applyCsrf("POST", post, "tok");
    expect(post.get(CSRF_HEADER)).toBe("tok");
    const get = new Headers({ [CSRF_HEADER]: "stale" });
    applyCsrf("GET", get, "tok");
    expect(get.has(CSRF_HEADER)).toBe(false);
  });

  it("is sent by the client after sign-in and not after sign-out", async () => {
    csrf.set("secret-1");
    const post = await capture((fetch) => api.POST("/api/auth/logout", { fetch }));
    expect(post.headers.get("X-CSRF-Token")).toBe("secret-1");
    const get = await capture((fetch) => api.GET("/api/auth/me", { fetch }));
    expect(get.headers.get("X-CSRF-Token")).toBeNull();
    csrf.clear();
    const after = await capture((fetch) => api.POST("/api/auth/logout", { fetch }));
    expect(after.headers.get("X-CSRF-Token")).toBeNull();
  });
});

describe("problemMessage", () => {
  it("joins title and detail of a problem document", () => {
    const body = { type: "about:blank", title: "Conflict", status: 409, detail: "has versions" };
    expect(problemMessage(body, 409)).toBe("Conflict: has versions");
  });

  it("lists validation errors with their paths", () => {
    const body = {
      title: "Unprocessable content",
      detail: "the orders cannot be read",
      errors: [{ path: "$.goals[0].id", message: "'G 1' is not a valid id" }],
    };
    expect(problemMessage(body, 422)).toBe(
      "Unprocessable content: the orders cannot be read ($.goals[0].id: 'G 1' is not a valid id)",
    );
  });

  it("falls back to a sentence for the status when the body says nothing", () => {
    expect(problemMessage(null, 429)).toMatch(/Too many attempts/);
    expect(problemMessage({}, 599)).toBe("The server answered 599.");
  });
});
