/** The addresses of the approval pages (parsed by router.ts, drawn by ApprovalPages). */
export type ApprovalRoute =
  | { page: "review"; mission: string; version: number }
  | { page: "document"; mission: string; version: number }
  | { page: "reviews" }
  | { page: "keys" }
  | { page: "audit" }
  | { page: "approval"; id: number };

export function parseApprovalRoute(path: string): ApprovalRoute | null {
  if (path === "/reviews") return { page: "reviews" };
  if (path === "/keys") return { page: "keys" };
  if (path === "/audit") return { page: "audit" };
  const approval = /^\/audit\/([1-9][0-9]{0,9})$/.exec(path);
  if (approval?.[1]) return { page: "approval", id: Number(approval[1]) };
  const review = /^\/missions\/([^/]+)\/versions\/([1-9][0-9]{0,9})\/(review|document)$/.exec(path);
  if (review?.[1] && review[2] && review[3]) {
    try {
      const page = review[3] === "document" ? "document" : "review";
      return { page, mission: decodeURIComponent(review[1]), version: Number(review[2]) };
    } catch {
      return null;
    }
  }
  return null;
}

/** Which roles may open each page (the server enforces the same on every call). */
export const PAGE_ROLES: Record<ApprovalRoute["page"], readonly string[]> = {
  review: ["operator", "supervisor", "auditor", "admin"],
  document: ["operator", "supervisor", "auditor", "admin"],
  reviews: ["supervisor"],
  keys: ["supervisor"],
  audit: ["supervisor", "auditor", "admin"],
  approval: ["supervisor", "auditor", "admin"],
};
