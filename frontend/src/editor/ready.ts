/**
 * When the canvas may say "ready" (data-ready, which the browser tests and operators' scripts
 * wait for) after the nodes got new positions: only once the view shows them. xyflow queues a
 * fit until its next node update and resolves the fit's promise when it has applied it; saying
 * ready at once read the previous viewport on a loaded machine (a handle outside the canvas).
 */

/** The part of xyflow's instance the view needs (kept narrow so it is testable without React). */
export interface ViewMover {
  fitView: (options?: object) => Promise<unknown>;
  setCenter: (x: number, y: number, options?: { zoom?: number }) => Promise<unknown>;
}

export interface Placed {
  position: { x: number; y: number };
  data: { start?: boolean };
}

/** Large drafts (over LARGE_GOALS) open at their start goal at a readable zoom instead of a fit:
 * a fit would mount every node at once to show text too small to read. */
export const START_ZOOM = 0.6;

/** Shows the laid-out nodes: all of them fitted, or for a large draft its start goal. */
export async function showLaidOut(flow: ViewMover, large: boolean, nodes: readonly Placed[], fit: object): Promise<void> {
  if (!large) {
    await flow.fitView(fit);
    return;
  }
  const start = nodes.find((n) => n.data.start) ?? nodes[0];
  if (start) await flow.setCenter(start.position.x + 300, start.position.y + 150, { zoom: START_ZOOM });
}

/** Calls `setReady(true)` once `show` has settled, or after `limitMs` should it never settle
 * (the limit only keeps "ready" from sticking; it is not how long a fit is expected to take). */
export function readyWhenShown(show: () => Promise<void>, setReady: (ready: boolean) => void, limitMs = 3000): Promise<void> {
  let timer: ReturnType<typeof setTimeout> | undefined;
  const limit = new Promise<void>((resolve) => {
    timer = setTimeout(resolve, limitMs);
  });
  return Promise.race([show().catch(() => undefined), limit]).then(() => {
    clearTimeout(timer);
    setReady(true);
  });
}
