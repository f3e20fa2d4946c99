/** The editor's server check: every edit's orders go to /api/validate (nothing stored; the
 * report is cached there by digest) and the newest answer is the report shown. */
import { type RefObject, useCallback, useEffect, useRef, useState } from "react";

import { api, type MissionDetail, type Report, unwrap } from "../api/client";
import type { Orders } from "./graph";
import type { Draft } from "./useDraftHistory";

export interface ServerCheck {
  report: Report | null;
  /** Milliseconds from the last edit (`editedAt`) to its report. */
  checkMs: number | null;
  /** The orders whose report is shown; a save of the same orders (a node moved, a layout
   * computed) sends no check. */
  lastChecked: RefObject<Orders | null>;
  editedAt: RefObject<number>;
  /** Re-reads the saved draft's report. */
  refreshChecks: () => Promise<void>;
  /** Checks orders; resolves whether the server answered with a report. */
  check: (orders: Orders) => Promise<boolean>;
}

export function useServerCheck(mission: MissionDetail, latest: RefObject<Draft>, onError: (e: unknown) => void): ServerCheck {
  const lastChecked = useRef<Orders | null>(mission.orders as Orders);
  const [report, setReport] = useState<Report | null>(null);
  const [checkMs, setCheckMs] = useState<number | null>(null);
  const editedAt = useRef<number>(0);

  const refreshChecks = useCallback(async () => {
    const path = { params: { path: { mission_id: mission.id } } };
    setReport(unwrap(await api.GET("/api/missions/{mission_id}/report", path)));
  }, [mission.id]);

  useEffect(() => {
    refreshChecks().catch(onError);
  }, [refreshChecks, onError]);

  // Shows the report if the orders are still the newest. Not queued behind a save in
  // progress: an edit is checked at once.
  const pendingCheck = useRef<{ orders: Orders; done: Promise<boolean> } | null>(null);
  const check = useCallback(
    (orders: Orders): Promise<boolean> => {
      if (orders === lastChecked.current) return Promise.resolve(true);
      if (pendingCheck.current?.orders === orders) return pendingCheck.current.done;
      const done = api.POST("/api/validate", { body: orders }).then(
        (x) => {
          performance.mark("editor:validated");
          if (!x.response.ok || !x.data) return false;
          if (latest.current.orders === orders) {
            lastChecked.current = orders;
            setReport(x.data);
            if (editedAt.current) setCheckMs(Math.round(performance.now() - editedAt.current));
          }
          return true;
        },
        () => false,
      );
      pendingCheck.current = { orders, done };
      return done;
    },
    [latest],
  );
  return { report, checkMs, lastChecked, editedAt, refreshChecks, check };
}
