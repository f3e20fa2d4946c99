/**
 * A change the server refused: the first error of its problem document mapped
 * to the field that caused it, so that the editor shows "Not saved: ..." beside that field (and
 * in Findings), on the panel that holds it, instead of only at the top of the page.
 */
import { ApiError } from "../api/client";
import type { Problem } from "../api/problem";
import type { Orders } from "./graph";

export interface Refusal {
  /** "$.norms[1].context: Field required" */
  message: string;
  /** The id of the input that shows the refused value, when one does. */
  fieldId: string | null;
  /** The tab of the lower panels that holds it, or null (the inspector, a goal selected). */
  panel: string | null;
  /** The goal or terminal to select (its inspector holds the field). */
  select: string | null;
}

const EXPRESSIONS = new Set(["forbidden", "obligated", "permitted"]);

/** The id of the index-th item of a list of the orders, when it is a list of items with ids. */
function idAt(list: unknown, index: number): string | null {
  const item: unknown = Array.isArray(list) ? list[index] : undefined;
  if (typeof item !== "object" || item === null || !("id" in item)) return null;
  return typeof item.id === "string" ? item.id : null;
}

/** Where the path `$.list[i].field...` points in the editor (null: nowhere in particular). */
export function fieldOf(orders: Orders, path: string): Omit<Refusal, "message"> {
  const none = { fieldId: null, panel: null, select: null };
  const m = /^\$\.(\w+)\[(\d+)\](?:\.(\w+))?/.exec(path);
  if (!m) return none;
  const [, list, at, field] = m;
  const index = Number(at);
  const lists: Record<string, unknown> = orders;
  const id = idAt(lists[list!], index);
  if (!id) return none;
  switch (list) {
    case "norms": {
      // A norm's missing or doubled modality (no field in the path) is its expression's fault.
      const which = !field || EXPRESSIONS.has(field) ? "expr" : field === "context" || field === "text" ? field : "expr";
      return { fieldId: `norm-${id}-${which}`, panel: "editor-norms", select: null };
    }
    case "constraints":
      return { fieldId: field === "text" ? `c-${id}-text` : `c-${id}-expr`, panel: "editor-constraints", select: null };
    case "goals":
      return { fieldId: field === "title" ? "goal-title" : null, panel: null, select: id };
    case "terminals":
      return { fieldId: field === "title" ? "terminal-title" : null, panel: null, select: id };
    case "areas":
      return { fieldId: null, panel: "editor-areas", select: null };
    case "vehicles":
      return { fieldId: null, panel: "editor-vehicle", select: null };
    default:
      return none;
  }
}

/** The refusal a failed save stands for, or null when the error is not a refused change (a
 * conflict, a lost connection: the page says those as before). */
export function refusalOf(error: unknown, orders: Orders): Refusal | null {
  if (!(error instanceof ApiError) || (error.status !== 422 && error.status !== 400)) return null;
  const body = (error.body ?? {}) as Problem;
  const first = Array.isArray(body.errors) ? body.errors.find((e) => e && typeof e.path === "string") : undefined;
  if (!first?.path) return { message: error.message, fieldId: null, panel: null, select: null };
  return { message: `${first.path}: ${first.message ?? "refused"}`, ...fieldOf(orders, first.path) };
}
