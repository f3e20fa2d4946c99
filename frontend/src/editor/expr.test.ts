/**
 * The editor's reading of expressions against the vectors it shares with the server
 * (__fixtures__/expressions.json; tests/orders/test_expression_vectors.py reads the same file).
 * The editor is held to the error's column (not its wording), the quantity names read and the
 * column of an unknown quantity; `browser` in a vector records where it knowingly differs.
 */
import { describe, expect, it } from "vitest";
import vectors from "./__fixtures__/expressions.json";
import { BUILTIN_QUANTITIES, checkExpr, parseExpr } from "./expr";

interface At {
  col: number;
}

interface Vector {
  text: string;
  error?: At & { message: string };
  reads?: string[];
  type_error?: At & { message: string };
  browser?: { error?: At | null; reads?: string[]; check?: At | null; note: string };
}

const entries: Vector[] = vectors.expressions;

/** What the editor should answer: the server's answer unless `browser` says otherwise. */
function expected(v: Vector): { error: At | null; reads: string[]; check: At | null } {
  const unknown = v.type_error?.message.startsWith("unknown quantity") ? { col: v.type_error.col } : null;
  const server = { error: v.error ? { col: v.error.col } : null, reads: v.reads ?? [], check: unknown };
  return { ...server, ...v.browser };
}

describe("expression vectors shared with the server", () => {
  it("knows the server's built-in quantities", () => {
    expect([...BUILTIN_QUANTITIES].sort()).toEqual(vectors.vocabulary);
  });

  it.each(entries)("reads $text like the server", (v) => {
    const want = expected(v);
    const parsed = parseExpr(v.text);
    expect(parsed.error ? { col: parsed.error.col } : null).toEqual(want.error);
    // The names read so far mean little after a syntax error; the column is what a user sees.
    if (want.error === null) expect([...new Set(parsed.names)]).toEqual(want.reads);
    const check = checkExpr(v.text, BUILTIN_QUANTITIES);
    expect(check ? { col: check.col } : null).toEqual(want.error ?? want.check);
  });
});
