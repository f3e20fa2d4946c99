/** The outcome probabilities of a review (issue 20) as table rows: exact figures or bounds. */
import type { Schema } from "../../api/client";

export type Bound = Schema<"BoundOut">;
export type OutcomeFigures = Schema<"ProbabilitiesOut">;

const QUANTITY: Record<string, string> = { energy_wh: "Expected energy (Wh)", duration_s: "Expected time (s)" };

export function figure(bound: Bound): string {
  const show = (x: number) => Number(x.toPrecision(6)).toString();
  return bound.min === bound.max ? show(bound.min) : `${show(bound.min)} to ${show(bound.max)}`;
}

export function probabilityRows(figures: OutcomeFigures): { what: string; value: string }[] {
  const rows = Object.entries(figures.terminals).map(([terminal, b]) => ({ what: `Ends at ${terminal}`, value: figure(b) }));
  rows.push({ what: "Any constraint violated", value: figure(figures.violation) });
  for (const [quantity, e] of Object.entries(figures.expected)) {
    const quantiles = e.quantiles
      ? ` (${Object.entries(e.quantiles).map(([level, v]) => `p${Number(level) * 100} ${v}`).join(", ")})`
      : "";
    rows.push({ what: QUANTITY[quantity] ?? quantity, value: figure(e) + quantiles });
  }
  return rows;
}

/** A path's probability as the server gives it: a number, or [min, max]. */
export function pathProbability(value: unknown): string | null {
  if (typeof value === "number") return Number(value.toPrecision(4)).toString();
  if (Array.isArray(value) && value.length === 2 && value.every((x) => typeof x === "number")) {
    return figure({ min: value[0] as number, max: value[1] as number });
  }
  return null;
}
