/**
 * No front-end function over MAX_LINES counted lines (blank and comment-only lines left out),
 * unless a "Length:" comment above it says why, or it is one of the long functions written
 * before the rule (ALLOWED, each with its reason; not in the editor). A function listed that got short is
 * taken off the list (the test says so), so the list only shrinks.
 */
import { describe, expect, it } from "vitest";

import { ALLOWED, MAX_LINES } from "./allowed";
import { functionLengths } from "./functionLength";

// Every source file of the app, read as text by Vite (no Node.js types needed); the tests and
// the generated API types are not app code.
const SOURCES = import.meta.glob(["../**/*.ts", "../**/*.tsx", "!../**/*.test.ts", "!../**/*.d.ts"], {
  query: "?raw",
  import: "default",
  eager: true,
}) as Record<string, string>;

// Parsing every file takes seconds on a loaded machine: done once, with a timeout that is a
// bound on a hang rather than on speed.
const PARSE_TIMEOUT_MS = 120_000;
let lengths: ReturnType<typeof functionLengths> | null = null;
function measured() {
  lengths ??= Object.entries(SOURCES).flatMap(([path, text]) => functionLengths(`src/${path.slice(3)}`, text));
  return lengths;
}

describe("function length", () => {
  it("measures blank and comment-only lines out, nested lines in", () => {
    const text = ["function outer() {", "", "  // why", "  const inner = () => {", "    return 1;", "  };", "  return inner;", "}"].join("\n");
    const lengths = functionLengths("x.ts", text);
    expect(lengths).toEqual([
      { name: "x.ts:outer", lines: 6, line: 1, reason: null },
      { name: "x.ts:inner", lines: 3, line: 4, reason: null },
    ]);
  });

  it("reads a reason from a Length: comment above the function or its statement", () => {
    const text = ["// Length: one table", "export function a() {}", "/** Length: a store */", "export const b = () => 1;"].join("\n");
    expect(functionLengths("x.ts", text).map((f) => f.reason)).toEqual(["one table", "a store"]);
  });

  it("reads the app's sources", () => {
    expect(Object.keys(SOURCES).length).toBeGreaterThan(50);
  });

  it(`keeps every function within ${MAX_LINES} lines unless it is allowed with a reason`, () => {
    const long = measured().filter((f) => f.lines > MAX_LINES && !(f.name in ALLOWED) && !f.reason);
    expect(long.map((f) => `${f.name} (line ${f.line}): ${f.lines} lines`)).toEqual([]);
  }, PARSE_TIMEOUT_MS);

  it("allows only functions that are still long, each with a reason", () => {
    const longest = new Map<string, number>();
    for (const f of measured()) longest.set(f.name, Math.max(longest.get(f.name) ?? 0, f.lines));
    const stale = Object.keys(ALLOWED).filter((name) => (longest.get(name) ?? 0) <= MAX_LINES);
    expect(stale).toEqual([]);
    expect(Object.entries(ALLOWED).filter(([, reason]) => reason.trim().length < 10)).toEqual([]);
  }, PARSE_TIMEOUT_MS);

  it("lists nothing of the editor: it is a composition of short hooks and panels", () => {
    expect(Object.keys(ALLOWED).filter((name) => name.startsWith("src/editor/"))).toEqual([]);
  });
});
