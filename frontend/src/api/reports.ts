/** The validation report of a mission's draft: the one place the app asks for `/report`. The
 * key carries the draft's digest, so a saved draft is a new report and an old one is not shown. */
import { type QueryClient, useQuery } from "@tanstack/react-query";

import { api, type Report, type Schema, unwrap } from "./client";

export const reportKeys = {
  all: ["reports"] as const,
  mission: (id: string) => ["reports", id] as const,
  draft: (id: string, digest: string) => ["reports", id, digest] as const,
};

export async function fetchReport(id: string): Promise<Report> {
  return unwrap(await api.GET("/api/missions/{mission_id}/report", { params: { path: { mission_id: id } } }));
}

export function useReport(id: string, digest: string) {
  return useQuery({ queryKey: reportKeys.draft(id, digest), queryFn: () => fetchReport(id) });
}

/** Asks for the draft's report now and keeps it under the digest it names. */
export async function loadReport(client: QueryClient, id: string): Promise<Report> {
  const report = await fetchReport(id);
  client.setQueryData(reportKeys.draft(id, report.digest), report);
  return report;
}

/** Checks orders not yet saved (POST /api/validate stores nothing): the report, or null when
 * the server refused or could not be reached (the editor then keeps its last report). */
export async function validateOrders(orders: Schema<"Orders">): Promise<Report | null> {
  const answer = await api.POST("/api/validate", { body: orders });
  return answer.response.ok && answer.data ? answer.data : null;
}
