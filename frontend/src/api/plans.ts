/** What the plan view draws of some orders, and the server's map tile setting. */
import { useQuery } from "@tanstack/react-query";

import { api, type Schema, unwrap } from "./client";

export type PlanData = Schema<"PlanViewOut">;
type Orders = Schema<"Orders">;

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
