/** The approval pages by name (their addresses are in src/routes.tsx). */
export type ApprovalPageName = "review" | "document" | "reviews" | "keys" | "audit" | "approval";

/** Which roles may open each page (the server enforces the same on every call). */
export const PAGE_ROLES: Record<ApprovalPageName, readonly string[]> = {
  review: ["operator", "supervisor", "auditor", "admin"],
  document: ["operator", "supervisor", "auditor", "admin"],
  reviews: ["supervisor"],
  keys: ["supervisor"],
  audit: ["supervisor", "auditor", "admin"],
  approval: ["supervisor", "auditor", "admin"],
};
