import { describe, expect, it } from "vitest";

import { parseRoute } from "../../router";
import { parseApprovalRoute, PAGE_ROLES } from "./routes";

describe("approval page addresses", () => {
  it("parses the review, audit, keys and reviews pages", () => {
    expect(parseRoute("/missions/search-and-sample/versions/3/review")).toEqual({
      name: "approvals",
      page: { page: "review", mission: "search-and-sample", version: 3 },
    });
    expect(parseApprovalRoute("/missions/a%20b/versions/2/document")).toEqual({
      page: "document",
      mission: "a b",
      version: 2,
    });
    expect(parseRoute("/audit/12")).toEqual({ name: "approvals", page: { page: "approval", id: 12 } });
    expect(parseApprovalRoute("/audit")).toEqual({ page: "audit" });
    expect(parseApprovalRoute("/keys")).toEqual({ page: "keys" });
    expect(parseApprovalRoute("/reviews")).toEqual({ page: "reviews" });
  });

  it("leaves other addresses alone", () => {
    expect(parseRoute("/missions/search-and-sample")).toEqual({ name: "mission", id: "search-and-sample", tab: "orders" });
    expect(parseRoute("/audit/0").name).toBe("notFound");
    expect(parseRoute("/missions/x/versions/v1/review").name).toBe("notFound");
  });

  it("offers keys and reviews to supervisors only, the audit pages to log readers", () => {
    expect(PAGE_ROLES.keys).toEqual(["supervisor"]);
    expect(PAGE_ROLES.audit).toEqual(["supervisor", "auditor", "admin"]);
  });
});
