import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";

import { readyWhenShown, showLaidOut, type ViewMover } from "./ready";

/** A promise settled by hand, as xyflow's fit is once it has applied the viewport. */
function deferred(): { promise: Promise<void>; resolve: () => void } {
  let resolve = () => {};
  const promise = new Promise<void>((r) => {
    resolve = r;
  });
  return { promise, resolve };
}

function fakeFlow(fit: Promise<void>): ViewMover & { fits: number; centres: [number, number, number | undefined][] } {
  const flow = {
    fits: 0,
    centres: [] as [number, number, number | undefined][],
    fitView: () => {
      flow.fits += 1;
      return fit;
    },
    setCenter: (x: number, y: number, o?: { zoom?: number }) => {
      flow.centres.push([x, y, o?.zoom]);
      return fit;
    },
  };
  return flow;
}

const nodes = [
  { position: { x: 0, y: 0 }, data: {} },
  { position: { x: 400, y: 100 }, data: { start: true } },
];

describe("the canvas says ready only once the laid-out view is shown", () => {
  beforeEach(() => {
    vi.useFakeTimers();
  });
  afterEach(() => {
    vi.useRealTimers();
  });

  /** Lays the nodes out with a view move that settles only when `finish` is called, after a
   * second in which nothing else would have settled it. */
  async function shownAfterASecond(large: boolean) {
    const move = deferred();
    const flow = fakeFlow(move.promise);
    const setReady = vi.fn();
    const done = readyWhenShown(() => showLaidOut(flow, large, nodes, {}), setReady);
    await vi.advanceTimersByTimeAsync(1000);
    const finish = async () => {
      move.resolve();
      await done;
    };
    return { flow, setReady, finish };
  }

  it("waits for the fit's promise, not for a frame or a short timer", async () => {
    const { flow, setReady, finish } = await shownAfterASecond(false);
    expect(flow.fits).toBe(1);
    expect(setReady).not.toHaveBeenCalled();
    await finish();
    expect(setReady).toHaveBeenCalledExactlyOnceWith(true);
  });

  it("a large draft is centred on its start goal, and ready waits for that too", async () => {
    const { flow, setReady, finish } = await shownAfterASecond(true);
    expect(flow.fits).toBe(0);
    expect(flow.centres).toEqual([[700, 250, 0.6]]);
    expect(setReady).not.toHaveBeenCalled();
    await finish();
    expect(setReady).toHaveBeenCalledExactlyOnceWith(true);
  });

  it("does not stick when the fit never settles or fails", async () => {
    const never = fakeFlow(new Promise<void>(() => {}));
    const setReady = vi.fn();
    const done = readyWhenShown(() => showLaidOut(never, false, nodes, {}), setReady, 3000);
    await vi.advanceTimersByTimeAsync(2999);
    expect(setReady).not.toHaveBeenCalled();
    await vi.advanceTimersByTimeAsync(1);
    await done;
    expect(setReady).toHaveBeenCalledWith(true);

    const failing = vi.fn();
    await readyWhenShown(() => Promise.reject(new Error("no viewport")), failing);
    expect(failing).toHaveBeenCalledWith(true);
  });
});
