/** The outcome probabilities of a review as table rows: exact figures or bounds. */
import type { Schema } from "../../api/client";

export type Bound = Schema<"BoundOut">;
export type OutcomeFigures = Schema<"ProbabilitiesOut">;

const QUANTITY: Record<string, string> = { energy_wh: "Expected energy", duration_s: "Expected time" };

/** A probability to four significant digits (a supervisor compares them, not their noise). */
function chance(x: number): string {
  return Number(x.toPrecision(4)).toString();
}

export function figure(bound: Bound): string {
  return bound.min === bound.max ? chance(bound.min) : `${chance(bound.min)} to ${chance(bound.max)}`;
}

/** A duration as "1 h 05 min", "4 min 20 s" or "38 s": whole seconds are what a plan is read in. */
export function duration(seconds: number): string {
  const s = Math.max(0, Math.round(seconds));
  const h = Math.floor(s / 3600);
  const m = Math.floor((s % 3600) / 60);
  if (h > 0) return `${h} h ${String(m).padStart(2, "0")} min`;
  if (m > 0) return `${m} min ${String(s % 60).padStart(2, "0")} s`;
  return `${s} s`;
}

/** A cost figure with its unit: energy in Wh to one decimal at most, time as a duration; another
 * quantity as a number of four significant digits (raw floats such as 339.0160693893765 say
 * nothing more and make the row unreadable). */
export function withUnit(quantity: string, value: number): string {
  if (quantity === "energy_wh") return `${value.toLocaleString("en-US", { maximumFractionDigits: 1 })} Wh`;
  if (quantity === "duration_s") return duration(value);
  return Number(value.toPrecision(4)).toLocaleString("en-US");
}

function costFigure(quantity: string, bound: Bound): string {
  return bound.min === bound.max
    ? withUnit(quantity, bound.min)
    : `${withUnit(quantity, bound.min)} to ${withUnit(quantity, bound.max)}`;
}

export function probabilityRows(figures: OutcomeFigures): { what: string; value: string }[] {
  const rows = Object.entries(figures.terminals).map(([terminal, b]) => ({ what: `Ends at ${terminal}`, value: figure(b) }));
  rows.push({ what: "Any constraint violated", value: figure(figures.violation) });
  for (const [quantity, e] of Object.entries(figures.expected)) {
    const quantiles = e.quantiles
      ? ` (${Object.entries(e.quantiles)
          .map(([level, v]) => `p${Math.round(Number(level) * 100)} ${withUnit(quantity, v)}`)
          .join(", ")})`
      : "";
    rows.push({ what: QUANTITY[quantity] ?? quantity, value: costFigure(quantity, e) + quantiles });
  }
  return rows;
}

/** A path's probability as the server gives it: a number, or [min, max]. */
export function pathProbability(value: unknown): string | null {
  if (typeof value === "number") return chance(value);
  if (Array.isArray(value) && value.length === 2 && value.every((x) => typeof x === "number")) {
    return figure({ min: value[0] as number, max: value[1] as number });
  }
  return null;
}
