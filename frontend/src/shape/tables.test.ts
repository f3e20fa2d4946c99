/**
 * DataTable is the one table of the app: no other component writes `<table>` markup, so a
 * caption, header scopes and the scrolling box cannot be forgotten in one list and not another.
 */
import { describe, expect, it } from "vitest";

import { tableBreaches } from "./tables";

// Every source file of the app, read as text by Vite; the tests and the generated API types are not app code.
const SOURCES = import.meta.glob(["../**/*.ts", "../**/*.tsx", "!../**/*.test.ts", "!../**/*.d.ts"], {
  query: "?raw",
  import: "default",
  eager: true,
}) as Record<string, string>;

// Parsing every file takes seconds on a loaded machine: a bound on a hang, not on speed.
const PARSE_TIMEOUT_MS = 120_000;

const at = (files: Record<string, string>) => tableBreaches(files).map((b) => b.at);

describe("one table component", () => {
  it("holds for the app", () => {
    const app = Object.fromEntries(Object.entries(SOURCES).map(([path, text]) => [`src/${path.slice(3)}`, text]));
    expect(Object.keys(app)).toContain("src/components/DataTable.tsx");
    expect(at(app)).toEqual([]);
  }, PARSE_TIMEOUT_MS);

  it("finds a component that draws its own table", () => {
    const page = ["export function Counts() {", "  return (", '    <table className="counts">', "      <tbody />", "    </table>", "  );", "}"].join("\n");
    expect(at({ "src/pages/Counts.tsx": page })).toEqual(["src/pages/Counts.tsx:3"]);
    const made = 'import { createElement } from "react";\nexport const T = () => createElement("table", null);';
    expect(at({ "src/pages/Made.ts": made })).toEqual(["src/pages/Made.ts:2"]);
  });

  it("lets DataTable draw it, and a word in a comment or a string pass", () => {
    expect(at({ "src/components/DataTable.tsx": "export const T = () => <table />;" })).toEqual([]);
    const prose = '// draws no <table> of its own\nexport const hint = "a <table> of figures";';
    expect(at({ "src/pages/Prose.tsx": prose })).toEqual([]);
  });
});
