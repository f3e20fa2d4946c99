import { createMemoryHistory } from "@tanstack/react-router";
import { describe, expect, it } from "vitest";

import { createAppRouter } from "./routes";
import { section } from "./Shell";

/** The route an address opens, with its params and search, or "notFound". */
async function open(href: string) {
  const router = createAppRouter(createMemoryHistory({ initialEntries: [href] }));
  await router.load();
  const leaf = router.state.matches.at(-1);
  // The router marks the match that draws the not-found page with `_notFound` (no public name).
  const missing = router.state.matches.some((m) => (m as { _notFound?: boolean })._notFound);
  return {
    route: missing ? "notFound" : leaf?.routeId,
    params: leaf?.params,
    search: leaf?.search,
  };
}

describe("the route tree", () => {
  it.each([
    ["/", "/"],
    ["/missions", "/missions"],
    ["/import", "/import"],
    ["/users", "/users"],
    ["/account", "/account"],
    ["/vehicles", "/vehicles"],
    ["/events", "/events"],
    ["/reviews", "/reviews"],
    ["/keys", "/keys"],
    ["/audit", "/audit"],
  ])("%s opens its page", async (href, route) => {
    expect((await open(href)).route).toBe(route);
  });

  it("a mission's page, with its id decoded and its tab", async () => {
    const page = await open("/missions/search%20and?tab=paths");
    expect(page.route).toBe("/missions/$missionId");
    expect(page.params).toEqual({ missionId: "search and" });
    expect(page.search).toEqual({ tab: "paths" });
    expect((await open("/missions/search-and-sample")).search).toEqual({});
  });

  it("review, document and audit record pages carry numbers", async () => {
    const review = await open("/missions/search-and-sample/versions/3/review");
    expect(review.route).toBe("/missions/$missionId/versions/$version/review");
    expect(review.params).toEqual({ missionId: "search-and-sample", version: 3 });
    const document = await open("/missions/a%20b/versions/2/document");
    expect(document.route).toBe("/missions/$missionId/versions/$version/document");
    expect(document.params).toEqual({ missionId: "a b", version: 2 });
    const record = await open("/audit/12");
    expect(record.route).toBe("/audit/$approvalId");
    expect(record.params).toEqual({ approvalId: 12 });
  });

  it.each(["/nope", "/audit/0", "/audit/x", "/audit/01", "/missions/x/versions/v1/review", "/missions/x/versions/0/document", "/missions/x/y"])(
    "%s is not found",
    async (href) => {
      expect((await open(href)).route).toBe("notFound");
    },
  );

  it("the sign-in address has a route (signed in, it goes on to the missions)", async () => {
    expect((await open("/login")).route).toBe("/login");
  });
});

describe("the main navigation's current entry", () => {
  it("marks the section a page belongs to", () => {
    expect(section("/")).toBe("missions");
    expect(section("/missions/x")).toBe("missions");
    expect(section("/missions/x/versions/2/review")).toBe("review");
    expect(section("/audit/12")).toBe("audit");
    expect(section("/keys")).toBe("keys");
  });
});
