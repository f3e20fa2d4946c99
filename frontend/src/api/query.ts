/**
 * Server state through TanStack Query: one client for the app, a key per resource (the
 * resource modules beside this one own their keys), and invalidation after every write so a
 * page shows what the server now holds without a reload of its own.
 */
import { QueryClient } from "@tanstack/react-query";

import { ApiError } from "./client";

/** A refusal (4xx) says something true about the request: asking again changes nothing. */
export function retryRequest(failures: number, error: unknown): boolean {
  if (error instanceof ApiError && error.status < 500) return false;
  return failures < 1;
}

export function makeQueryClient(): QueryClient {
  return new QueryClient({
    defaultOptions: {
      queries: {
        retry: retryRequest,
        // The pages ask again when they mount or a write invalidates them, not when the
        // window regains focus: a supervisor reading a review must not see it change under them.
        refetchOnWindowFocus: false,
        // A page asks again each time it opens (what it last saw is shown meanwhile): lists
        // change through other people's work, which no write here invalidates.
        staleTime: 0,
      },
      mutations: { retry: false },
    },
  });
}

export const queryClient = makeQueryClient();
