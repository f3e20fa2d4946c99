/**
 * CSRF handling for the cookie session (docs/api.md, Authentication): every state-changing
 * request made with the session cookie carries the token from login or `GET /api/auth/me`
 * in the `X-CSRF-Token` header. Safe methods never carry it, so it never leaks into caches
 * or logs of read-only requests.
 */

export const CSRF_HEADER = "X-CSRF-Token";

const SAFE_METHODS = new Set(["GET", "HEAD", "OPTIONS", "TRACE"]);

export function isStateChanging(method: string): boolean {
  return !SAFE_METHODS.has(method.toUpperCase());
}

/** Holds the token of the current session; cleared on sign-out or when the session ends. */
export class CsrfToken {
  private value: string | null = null;

  set(token: string | null | undefined): void {
    this.value = token ? token : null;
  }

  get(): string | null {
    return this.value;
  }

  clear(): void {
    this.value = null;
  }
}

/** Adds the header to a state-changing request when a token is known (mutates `headers`). */
export function applyCsrf(method: string, headers: Headers, token: string | null): void {
  if (token && isStateChanging(method)) {
    headers.set(CSRF_HEADER, token);
  } else {
    headers.delete(CSRF_HEADER);
  }
}
