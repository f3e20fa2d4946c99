/** Small display helpers, kept pure so they can be tested without a browser. */

export function plural(count: number, one: string, many = `${one}s`): string {
  return `${count.toLocaleString("en-US")} ${count === 1 ? one : many}`;
}

/** `2026-11-28 07:43` in the given time zone (the browser's own by default). */
export function formatDateTime(iso: string | null | undefined, timeZone?: string): string {
  if (!iso) return "";
  const date = new Date(iso);
  if (Number.isNaN(date.getTime())) return iso;
  const parts = new Intl.DateTimeFormat("en-GB", {
    year: "numeric",
    month: "2-digit",
    day: "2-digit",
    hour: "2-digit",
    minute: "2-digit",
    hourCycle: "h23",
    timeZone,
  }).formatToParts(date);
  const get = (type: string) => parts.find((p) => p.type === type)?.value ?? "";
  return `${get("year")}-${get("month")}-${get("day")} ${get("hour")}:${get("minute")}`;
}

/** `sha256:1a2b3c4d5e6f…` — enough of a digest to tell versions apart on screen. */
export function shortDigest(digest: string | null | undefined, keep = 12): string {
  if (!digest) return "";
  const [algorithm, hex] = digest.includes(":") ? digest.split(":", 2) : ["", digest];
  const short = (hex ?? "").length > keep ? `${(hex ?? "").slice(0, keep)}…` : hex ?? "";
  return algorithm ? `${algorithm}:${short}` : short;
}

/** Human words for a mission status such as `in_review`. */
export function statusLabel(status: string | null | undefined): string {
  if (!status) return "";
  const words = status.replace(/[_-]+/g, " ").trim();
  return words.charAt(0).toUpperCase() + words.slice(1);
}

/** `19,800` — a count or measure, or an empty string when the value is missing. */
export function formatNumber(value: number | null | undefined): string {
  return typeof value === "number" && Number.isFinite(value) ? value.toLocaleString("en-US") : "";
}
