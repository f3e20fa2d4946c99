/** The auto layout off the page's thread (ELK on a few hundred nodes takes long enough to
 * freeze input): orders in, positions out. */
import { autoLayout, type Sizes } from "./layout";
import type { Orders } from "./graph";

export interface LayoutRequest {
  id: number;
  orders: Orders;
  sizes: Sizes;
  aspect?: number;
}

// A listener, not `self.onmessage`: elkjs's bundled build, first run inside a worker (on the
// first layout), sets `self.onmessage` to its own dispatcher, which ignores these requests; a
// handler set here was replaced so, and every layout after the first in a page went
// unanswered until the client's patience ran out (10 s, then the linear layout).
self.addEventListener("message", (event: MessageEvent<LayoutRequest>) => {
  const { id, orders, sizes, aspect } = event.data;
  autoLayout(orders, sizes, aspect).then(
    (layout) => self.postMessage({ id, layout }),
    (error: unknown) => self.postMessage({ id, error: String(error) }),
  );
});
