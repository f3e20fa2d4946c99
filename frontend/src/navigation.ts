import { useEffect, useState } from "react";

import { parseRoute, type Route } from "./router";

const EVENT = "countersign:navigate";

/** Goes to `href` inside the app without reloading the page. */
export function navigate(href: string, options: { replace?: boolean } = {}): void {
  if (options.replace) {
    window.history.replaceState(null, "", href);
  } else {
    window.history.pushState(null, "", href);
  }
  window.dispatchEvent(new Event(EVENT));
}

/** Changes the query string of the current page (filters, pages) without a new history entry. */
export function replaceQuery(params: Record<string, string | null | undefined>): void {
  const url = new URL(window.location.href);
  for (const [key, value] of Object.entries(params)) {
    if (value) url.searchParams.set(key, value);
    else url.searchParams.delete(key);
  }
  window.history.replaceState(null, "", `${url.pathname}${url.search}`);
}

function current(): { route: Route; search: string } {
  return {
    route: parseRoute(window.location.pathname, window.location.search),
    search: window.location.search,
  };
}

export function useLocationRoute(): { route: Route; search: string } {
  const [state, setState] = useState(current);
  useEffect(() => {
    const update = () => setState(current());
    window.addEventListener("popstate", update);
    window.addEventListener(EVENT, update);
    return () => {
      window.removeEventListener("popstate", update);
      window.removeEventListener(EVENT, update);
    };
  }, []);
  return state;
}
