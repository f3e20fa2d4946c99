/**
 * The browser history the app's router listens to. Code outside React (the editor's dialogs,
 * a page after a write) goes somewhere with `navigate(href)`; the router sees the change and
 * draws the page. Created on first use, so modules importing this one load under Node (tests).
 */
import { createBrowserHistory, type RouterHistory } from "@tanstack/react-router";

let browser: RouterHistory | null = null;

export function appHistory(): RouterHistory {
  browser ??= createBrowserHistory();
  return browser;
}

/** Goes to `href` inside the app without reloading the page. */
export function navigate(href: string, options: { replace?: boolean } = {}): void {
  if (options.replace) appHistory().replace(href);
  else appHistory().push(href);
}

/** Changes the query string of the current page (filters, pages) without a new history entry. */
export function replaceQuery(params: Record<string, string | null | undefined>): void {
  const url = new URL(window.location.href);
  for (const [key, value] of Object.entries(params)) {
    if (value) url.searchParams.set(key, value);
    else url.searchParams.delete(key);
  }
  appHistory().replace(`${url.pathname}${url.search}`);
}
