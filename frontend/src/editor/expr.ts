/**
 * Client-side reading of the orders' expression language (DESIGN.md, "Expressions"), for inline
 * parse errors and completion while typing. It mirrors the server's grammar
 * (backend/countersign/orders/expressions/); the server stays the judge (EXPR findings).
 *
 *   implies := or ('implies' implies)?            weakest, right-associative
 *   or      := and ('or' and)*
 *   and     := not ('and' not)*
 *   not     := 'not' not | compare
 *   compare := sum (('==' | '!=' | '<' | '<=' | '>' | '>=') sum)*
 *   sum     := product (('+' | '-') product)*
 *   product := unary (('*' | '/') unary)*
 *   unary   := '-' unary | primary
 *   primary := number | 'string' | true | false | name | behavior | area
 *            | context '(' 'string' ')' | '(' implies ')'
 */
import type { Orders } from "./graph";

export type TokenKind = "number" | "string" | "name" | "op" | "lparen" | "rparen" | "end";

export interface Token {
  kind: TokenKind;
  text: string;
  /** 1-based column of the token's first character. */
  col: number;
}

export interface ExprError {
  message: string;
  /** 1-based column. */
  col: number;
}

const KEYWORDS = new Set(["and", "or", "not", "implies", "true", "false", "behavior", "area", "context"]);
const COMPARISONS = new Set(["==", "!=", "<", "<=", ">", ">="]);

/** Quantities any orders may read without declaring them (the server's maritime vocabulary). */
export const BUILTIN_QUANTITIES = [
  "depth_m", "altitude_m", "speed_mps", "heading_deg", "pitch_deg", "roll_deg", "latitude_deg",
  "longitude_deg", "lane_distance_m", "contact_distance_m", "contact_detection_range_m",
  "contact_count", "shore_distance_m", "base_distance_m", "nav_error_m", "current_mps",
  "wave_height_m", "sea_state", "visibility_m", "water_temperature_c", "battery_pct",
  "battery_reserve_pct", "energy_wh", "duration_s", "elapsed_s", "comms_ok", "gps_fix",
  "surfaced", "safety_equipment_ok", "mission_systems_ok",
];

export function tokenize(text: string): { tokens: Token[]; error?: ExprError } {
  const tokens: Token[] = [];
  let i = 0;
  while (i < text.length) {
    const ch = text[i]!;
    const col = i + 1;
    if (/\s/.test(ch)) {
      i += 1;
    } else if (/[0-9.]/.test(ch)) {
      const m = /^(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?/.exec(text.slice(i));
      if (!m) return { tokens, error: { message: `unexpected '${ch}'`, col } };
      tokens.push({ kind: "number", text: m[0], col });
      i += m[0].length;
    } else if (/[A-Za-z_]/.test(ch)) {
      const m = /^[A-Za-z_][A-Za-z0-9_]*/.exec(text.slice(i))!;
      tokens.push({ kind: "name", text: m[0], col });
      i += m[0].length;
    } else if (ch === "'" || ch === '"') {
      const end = text.indexOf(ch, i + 1);
      if (end < 0) return { tokens, error: { message: "unterminated string", col } };
      tokens.push({ kind: "string", text: text.slice(i + 1, end), col });
      i = end + 1;
    } else if (ch === "(") {
      tokens.push({ kind: "lparen", text: ch, col });
      i += 1;
    } else if (ch === ")") {
      tokens.push({ kind: "rparen", text: ch, col });
      i += 1;
    } else {
      const two = text.slice(i, i + 2);
      if (COMPARISONS.has(two)) {
        tokens.push({ kind: "op", text: two, col });
        i += 2;
      } else if ("+-*/<>".includes(ch)) {
        tokens.push({ kind: "op", text: ch, col });
        i += 1;
      } else if (ch === "=" || ch === "!") {
        return { tokens, error: { message: `'${ch}' alone is not an operator; write '==' or '!='`, col } };
      } else {
        return { tokens, error: { message: `unexpected '${ch}'`, col } };
      }
    }
  }
  tokens.push({ kind: "end", text: "", col: text.length + 1 });
  return { tokens };
}

class Fail extends Error {
  constructor(readonly at: ExprError) {
    super(at.message);
  }
}

function describe(t: Token): string {
  return t.kind === "end" ? "the end" : t.kind === "string" ? `'${t.text}'` : `'${t.text}'`;
}

/** Parses an expression; answers the quantity names it reads, or the first error's position. */
// Length: one recursive-descent parser: its grammar rules read together as the grammar.
export function parseExpr(text: string): { names: string[]; error?: ExprError } {
  if (text.trim() === "") return { names: [], error: { message: "the expression is empty", col: 1 } };
  const { tokens, error } = tokenize(text);
  if (error) return { names: [], error };
  const names: string[] = [];
  let p = 0;
  const peek = () => tokens[p]!;
  const isWord = (w: string) => peek().kind === "name" && peek().text === w;
  const next = () => tokens[p++]!;

  const primary = (): void => {
    const t = next();
    if (t.kind === "number" || t.kind === "string") return;
    if (t.kind === "lparen") {
      implies();
      const close = next();
      if (close.kind !== "rparen") throw new Fail({ message: `expected ')' but found ${describe(close)}`, col: close.col });
      return;
    }
    if (t.kind === "name") {
      if (t.text === "context") {
        const open = next();
        if (open.kind !== "lparen") throw new Fail({ message: "expected '(' after context", col: open.col });
        const tag = next();
        if (tag.kind !== "string") throw new Fail({ message: "context needs a quoted tag, e.g. context('shipping_lane')", col: tag.col });
        const close = next();
        if (close.kind !== "rparen") throw new Fail({ message: `expected ')' but found ${describe(close)}`, col: close.col });
        return;
      }
      if (["and", "or", "not", "implies"].includes(t.text)) {
        throw new Fail({ message: `expected a value but found '${t.text}'`, col: t.col });
      }
      if (!KEYWORDS.has(t.text)) names.push(t.text);
      return;
    }
    const before = tokens[p - 2];
    throw new Fail({
      message: t.kind === "end" && before ? `expected a value after '${before.text}'` : `expected a value but found ${describe(t)}`,
      col: t.col,
    });
  };
  const unary = (): void => {
    if (peek().kind === "op" && peek().text === "-") {
      next();
      unary();
    } else primary();
  };
  const product = (): void => {
    unary();
    while (peek().kind === "op" && (peek().text === "*" || peek().text === "/")) {
      next();
      unary();
    }
  };
  const sum = (): void => {
    product();
    while (peek().kind === "op" && (peek().text === "+" || peek().text === "-")) {
      next();
      product();
    }
  };
  const compare = (): void => {
    sum();
    while (peek().kind === "op" && COMPARISONS.has(peek().text)) {
      next();
      sum();
    }
  };
  const not = (): void => {
    if (isWord("not")) {
      next();
      not();
    } else compare();
  };
  const and = (): void => {
    not();
    while (isWord("and")) {
      next();
      not();
    }
  };
  const or = (): void => {
    and();
    while (isWord("or")) {
      next();
      and();
    }
  };
  function implies(): void {
    or();
    if (isWord("implies")) {
      next();
      implies();
    }
  }
  try {
    implies();
    const t = peek();
    if (t.kind !== "end") throw new Fail({ message: `unexpected ${describe(t)}; expected an operator or the end`, col: t.col });
  } catch (e) {
    if (e instanceof Fail) return { names, error: e.at };
    throw e;
  }
  return { names };
}

/** Every quantity name an expression of these orders may read (mirrors the server's table). */
export function knownQuantities(orders: Partial<Pick<Orders, "quantities" | "goals" | "vehicle" | "vehicles">>): string[] {
  const names = new Set<string>(BUILTIN_QUANTITIES);
  for (const q of Object.keys(orders.quantities ?? {})) names.add(q);
  for (const g of orders.goals ?? []) for (const q of Object.keys(g.envelope ?? {})) names.add(q);
  const v = (orders.vehicles ?? []).find((x) => x.id === orders.vehicle);
  if (v) {
    for (const q of Object.keys(v.envelope ?? {})) names.add(q);
    for (const f of v.features ?? []) for (const q of f.measures ?? []) names.add(q);
  }
  return [...names].sort();
}

/** Problems to show under an expression field: the parse error, else unknown quantities. */
export function checkExpr(text: string, known: string[]): ExprError | null {
  const parsed = parseExpr(text);
  if (parsed.error) return parsed.error;
  const set = new Set(known);
  const unknown = parsed.names.find((n) => !set.has(n));
  if (unknown) {
    const col = text.search(new RegExp(`\\b${unknown}\\b`)) + 1;
    return { message: `unknown quantity '${unknown}'`, col: Math.max(col, 1) };
  }
  return null;
}

/** The word being typed at the caret: its start offset and text. */
export function wordAt(text: string, caret: number): { start: number; prefix: string } {
  let start = caret;
  while (start > 0 && /[A-Za-z0-9_]/.test(text[start - 1]!)) start -= 1;
  const prefix = text.slice(start, caret);
  return /^[A-Za-z_]/.test(prefix) ? { start, prefix } : { start: caret, prefix: "" };
}

/** Completions for the word at the caret (quantities first, then keywords). */
export function completions(text: string, caret: number, known: string[]): { start: number; items: string[] } {
  const { start, prefix } = wordAt(text, caret);
  if (prefix === "") return { start, items: [] };
  // Inside a quoted string there is nothing to complete.
  const quotes = (text.slice(0, start).match(/['"]/g) ?? []).length;
  if (quotes % 2 === 1) return { start, items: [] };
  const lower = prefix.toLowerCase();
  const words = [...known, "and", "or", "not", "implies", "true", "false", "behavior", "area", "context"];
  const items = [...new Set(words)].filter((w) => w.toLowerCase().startsWith(lower) && w !== prefix).slice(0, 12);
  return { start, items };
}

/** Replaces the word at the caret with a completion; answers the new text and caret. */
export function applyCompletion(text: string, caret: number, word: string): { text: string; caret: number } {
  const { start } = wordAt(text, caret);
  let end = caret;
  while (end < text.length && /[A-Za-z0-9_]/.test(text[end]!)) end += 1;
  const inserted = word === "context" ? "context('" : word;
  const updated = text.slice(0, start) + inserted + text.slice(end);
  return { text: updated, caret: start + inserted.length };
}
