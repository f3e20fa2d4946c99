/**
 * The Content-Type to send an uploaded or pasted orders document with: from the file name
 * first, then the browser's guess, then a look at the text itself.
 */
export function contentTypeFor(name: string, browserType = "", text = ""): string {
  const lower = name.toLowerCase();
  if (lower.endsWith(".json")) return "application/json";
  if (lower.endsWith(".xml") || lower.endsWith(".avcl")) return "application/xml";
  if (lower.endsWith(".ttl") || lower.endsWith(".turtle")) return "text/turtle";
  if (browserType === "application/json" || browserType.endsWith("+json")) return "application/json";
  if (browserType.endsWith("/xml") || browserType.endsWith("+xml")) return "application/xml";
  if (browserType === "text/turtle") return "text/turtle";
  const start = text.trimStart();
  if (start.startsWith("{")) return "application/json";
  if (start.startsWith("<")) return "application/xml";
  if (start.startsWith("@prefix") || start.startsWith("PREFIX") || start.startsWith("@base")) {
    return "text/turtle";
  }
  return "application/octet-stream";
}
