/** What the plan view draws of some orders, and the server's map tile setting. */
import { useQuery } from "@tanstack/react-query";

import { api, type paths, type Schema, unwrap } from "./client";

export type PlanData = Schema<"PlanViewOut">;
type Orders = Schema<"Orders">;
type ProblemIn = NonNullable<paths["/api/missions/{mission_id}/plan-problem"]["post"]["requestBody"]>["content"]["application/json"];
type Problem = Schema<"PlanProblem">;

export const planKeys = {
  view: (orders: string) => ["plan-view", orders] as const,
  config: ["client-config"] as const,
};

/** The plan of `orders`, keyed by their JSON text (the same orders, the same plan). */
export function usePlanView(orders: Orders) {
  const text = JSON.stringify(orders);
  return useQuery({
    queryKey: planKeys.view(text),
    queryFn: async (): Promise<PlanData> => unwrap(await api.POST("/api/plan-view", { body: orders })),
  });
}

/** The server's settings for the browser; they do not change while the page is open. */
export function useClientConfig() {
  return useQuery({
    queryKey: planKeys.config,
    queryFn: async () => unwrap(await api.GET("/api/client-config")),
    staleTime: Infinity,
  });
}

/** The planning problem the server builds from a mission's areas and the dialog's choices (it
 * stores nothing). */
export async function buildPlanProblem(mission: string, body: ProblemIn): Promise<Problem> {
  return unwrap(await api.POST("/api/missions/{mission_id}/plan-problem", { params: { path: { mission_id: mission } }, body }));
}

/** The server's plan for a problem (computed, not stored). */
export async function solvePlan(problem: Problem) {
  return unwrap(await api.POST("/api/plan", { body: problem }));
}
