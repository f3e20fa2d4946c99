import type { ReactNode } from "react";

/** An error that screen readers announce; `null` renders nothing. */
export function ErrorMessage({ error }: { error: unknown }) {
  if (!error) return null;
  const text = error instanceof Error ? error.message : String(error);
  return (
    <p className="message error" role="alert">
      {text}
    </p>
  );
}

export function Notice({ children }: { children: ReactNode }) {
  return (
    <p className="message notice" role="status">
      {children}
    </p>
  );
}

export function Loading({ what }: { what: string }) {
  return (
    <p className="loading" role="status" aria-live="polite">
      Loading {what}…
    </p>
  );
}

export function CheckBadge({
  ok,
  errors,
  warnings,
}: {
  ok: boolean | null | undefined;
  errors: number | null | undefined;
  warnings: number | null | undefined;
}) {
  if (ok === null || ok === undefined) {
    return <span className="badge muted">not checked</span>;
  }
  const parts: string[] = [];
  if (errors) parts.push(`${errors} error${errors === 1 ? "" : "s"}`);
  if (warnings) parts.push(`${warnings} warning${warnings === 1 ? "" : "s"}`);
  return (
    <span className={`badge ${ok ? "ok" : "bad"}`}>
      {ok ? "OK" : "Not OK"}
      {parts.length ? ` · ${parts.join(", ")}` : ""}
    </span>
  );
}
