/** Addresses the app builds by hand (the route tree itself is in routes.tsx). */

/** A mission's page, on `tab` (the orders tab has no `?tab=`). */
export function missionHref(id: string, tab?: string): string {
  const base = `/missions/${encodeURIComponent(id)}`;
  return tab && tab !== "orders" ? `${base}?tab=${encodeURIComponent(tab)}` : base;
}
