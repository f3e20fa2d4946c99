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

self.onmessage = (event: MessageEvent<LayoutRequest>) => {
  const { id, orders, sizes, aspect } = event.data;
  autoLayout(orders, sizes, aspect).then(
    (layout) => self.postMessage({ id, layout }),
    (error: unknown) => self.postMessage({ id, error: String(error) }),
  );
};
