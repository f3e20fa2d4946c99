/** Runs the auto layout in a Web Worker (layout.worker.ts), one worker per page, falling back
 * to the page's thread where workers are not available (tests under Node). */
import type { Layout, Orders } from "./graph";
import { autoLayout, layeredLayout, type Sizes } from "./layout";
import layoutWorkerSrc from "./layout.worker.ts?worker&url";

let worker: Worker | null = null;
let nextId = 1;
const waiting = new Map<number, { resolve: (l: Layout) => void; reject: (e: Error) => void }>();

interface ScriptUrlPolicy {
  createScriptURL: (url: string) => unknown;
}
declare global {
  // Trusted Types (Chromium) are not yet in TypeScript's DOM library.
  interface Window {
    trustedTypes?: { createPolicy: (name: string, rules: ScriptUrlPolicy) => ScriptUrlPolicy };
  }
}
let policy: ScriptUrlPolicy | null | undefined;
/** The page's CSP requires Trusted Types for script URLs and allows one policy,
 * `layout-worker`: it passes only this app's own layout worker script, same origin. */
function workerUrl(url: URL): string | URL {
  const tt = window.trustedTypes;
  if (!tt) return url;
  policy ??= tt.createPolicy("layout-worker", {
    createScriptURL: (raw: string) => {
      const u = new URL(raw, window.location.href);
      if (u.origin !== window.location.origin || !/\/layout\.worker[-.\w]*\.(js|ts)$/.test(u.pathname)) {
        throw new TypeError(`not the layout worker: ${raw}`);
      }
      return u.href;
    },
  });
  return policy.createScriptURL(url.href) as string;
}

function layoutWorker(): Worker | null {
  if (typeof Worker === "undefined") return null;
  if (!worker) {
    worker = new Worker(workerUrl(new URL(layoutWorkerSrc, window.location.href)), { type: "module" });
    worker.onmessage = (event: MessageEvent<{ id: number; layout?: Layout; error?: string }>) => {
      const job = waiting.get(event.data.id);
      waiting.delete(event.data.id);
      if (event.data.layout) job?.resolve(event.data.layout);
      else job?.reject(new Error(event.data.error ?? "the layout failed"));
    };
    worker.onerror = () => {
      for (const job of waiting.values()) job.reject(new Error("the layout worker failed"));
      waiting.clear();
      worker = null;
    };
  }
  return worker;
}

/** The canvas's width : height, the aspect ratio long chains wrap to. */
export function canvasAspect(): number | undefined {
  const pane = document.querySelector(".editor-canvas")?.getBoundingClientRect();
  return pane && pane.height > 0 ? Math.min(3, Math.max(0.8, pane.width / pane.height)) : undefined;
}

/** A worker that has not answered in this long is dropped and the linear layout done on the page. */
const WORKER_PATIENCE_MS = 10_000;

export function layoutOffThread(orders: Orders, sizes: Sizes = {}, aspect?: number): Promise<Layout> {
  const w = layoutWorker();
  if (!w) return autoLayout(orders, sizes, aspect);
  const id = nextId++;
  return new Promise<Layout>((resolve, reject) => {
    const timer = window.setTimeout(() => {
      waiting.delete(id);
      w.terminate();
      if (worker === w) worker = null;
      resolve(layeredLayout(orders, aspect)); // linear: never ELK on the page's thread
    }, WORKER_PATIENCE_MS);
    waiting.set(id, {
      resolve: (l) => {
        window.clearTimeout(timer);
        resolve(l);
      },
      reject: (e) => {
        window.clearTimeout(timer);
        try {
          resolve(layeredLayout(orders, aspect));
        } catch {
          reject(e);
        }
      },
    });
    w.postMessage({ id, orders, sizes, aspect });
  });
}
