/** The editor's server check: every edit's orders go to /api/validate (nothing stored; the
 * report is cached there by digest) and the newest answer is the report shown (in the store).
 * The saved draft's report is read through the query cache (queries.ts). */
import { useQueryClient } from "@tanstack/react-query";
import { useCallback, useEffect, useRef } from "react";

import type { Report } from "../api/client";
import { validateOrders } from "../api/reports";
import type { Orders } from "./graph";
import { fetchSavedReport } from "./queries";
import { useEditorApi } from "./store";

export interface ServerCheck {
  /** Re-reads the saved draft's report. */
  refreshChecks: () => Promise<void>;
  /** Checks orders; resolves whether the server answered with a report. */
  check: (orders: Orders) => Promise<boolean>;
}

/** `opening`: the saved draft's report as the page asked for it beside the mission (null when it
 * is not of this draft or failed); without it the report is asked for here. */
export function useServerCheck(opening: Promise<Report | null> | null = null): ServerCheck {
  const store = useEditorApi();
  const client = useQueryClient();

  const refreshChecks = useCallback(async () => {
    store.getState().showReport(await fetchSavedReport(client, store.getState().missionId, true));
  }, [store, client]);

  useEffect(() => {
    if (store.getState().report) return; // it came with the mission (the store opened with it)
    const first = opening
      ? opening.then((report) => {
          if (!report) return refreshChecks();
          if (!store.getState().report) store.getState().showReport(report); // unless an edit's check came first
        })
      : refreshChecks();
    first.catch((e: unknown) => store.getState().failed(e));
  }, [refreshChecks, store, opening]);

  // Shows the report if the orders are still the newest. Not queued behind a save in
  // progress: an edit is checked at once.
  const pendingCheck = useRef<{ orders: Orders; done: Promise<boolean> } | null>(null);
  const check = useCallback(
    (orders: Orders): Promise<boolean> => {
      if (orders === store.getState().lastChecked) return Promise.resolve(true);
      if (pendingCheck.current?.orders === orders) return pendingCheck.current.done;
      const done = validateOrders(orders).then(
        (report) => {
          performance.mark("editor:validated");
          if (!report) return false;
          const now = store.getState();
          if (now.history.present.orders === orders) {
            now.checked(orders, report, now.editedAt ? Math.round(performance.now() - now.editedAt) : null);
          }
          return true;
        },
        () => false,
      );
      pendingCheck.current = { orders, done };
      return done;
    },
    [store],
  );
  return { refreshChecks, check };
}
