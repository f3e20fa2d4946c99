/**
 * The two items of a pair in an answer. The schema says "exactly two" (a Pydantic tuple), but
 * openapi-fetch's `Readable` reads tuples as arrays, so the type allows a short one: a missing
 * item reads as `missing` (NaN for a coordinate or a bound: drawn nowhere, shown as "—")
 * instead of being cast away.
 */
export function pairOf<T>(values: readonly T[], missing: T): [T, T] {
  return [values[0] ?? missing, values[1] ?? missing];
}

/** A pair of numbers (a point, an interval); NaN where the answer lacks one. */
export function numberPair(values: readonly number[]): [number, number] {
  return pairOf(values, NaN);
}
