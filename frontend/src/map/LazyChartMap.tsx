/** The chart, loaded on demand: MapLibre and the coastline are a chunk of their own that only the
 * pages showing a map fetch (vite splits at this dynamic import). A map that cannot be drawn
 * (no WebGL, a blocked worker) says so in words and leaves the rest of the page working. */
import { Component, lazy, type ReactNode, Suspense } from "react";

import type { ChartMapProps } from "./types";

const ChartMapImpl = lazy(() => import("./ChartMap"));

class MapFailure extends Component<{ children: ReactNode }, { error: string | null }> {
  state = { error: null as string | null };
  static getDerivedStateFromError(error: unknown) {
    return { error: error instanceof Error ? error.message : String(error) };
  }
  render() {
    if (this.state.error !== null) {
      return (
        <p className="error" role="alert" data-testid="map-failure">
          The map could not be drawn in this browser ({this.state.error}); the vertices and findings below still work.
        </p>
      );
    }
    return this.props.children;
  }
}

export function ChartMap(props: ChartMapProps) {
  return (
    <MapFailure>
      <Suspense fallback={<p className="loading">Loading the map…</p>}>
        <ChartMapImpl {...props} />
      </Suspense>
    </MapFailure>
  );
}
