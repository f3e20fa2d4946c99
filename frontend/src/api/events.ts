/** The activity log as a resource: filtered, paged by the last id seen. */
import { keepPreviousData, useQuery } from "@tanstack/react-query";

import { api, type EventList, unwrap, type paths } from "./client";

export type EventQuery = NonNullable<paths["/api/events"]["get"]["parameters"]["query"]>;

export const eventKeys = {
  all: ["events"] as const,
  list: (query: EventQuery) => ["events", "list", query] as const,
};

export async function listEvents(query: EventQuery): Promise<EventList> {
  return unwrap(await api.GET("/api/events", { params: { query } }));
}

export function useEvents(query: EventQuery) {
  return useQuery({
    queryKey: eventKeys.list(query),
    queryFn: () => listEvents(query),
    placeholderData: keepPreviousData,
  });
}
