/** The chart, loaded on demand: MapLibre and the coastline are a chunk of their own that only the
 * pages showing a map fetch (vite splits at this dynamic import). */
import { lazy, Suspense } from "react";

import type { ChartMapProps } from "./types";

const ChartMapImpl = lazy(() => import("./ChartMap"));

export function ChartMap(props: ChartMapProps) {
  return (
    <Suspense fallback={<p className="loading">Loading the map…</p>}>
      <ChartMapImpl {...props} />
    </Suspense>
  );
}
