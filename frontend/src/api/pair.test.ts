import { describe, expect, it } from "vitest";

import { fromMetres } from "../editor/planview";
import { numberPair, pairOf } from "./pair";

describe("pairs read from answers", () => {
  it("gives both items of a whole pair", () => {
    expect(numberPair([3, -4])).toEqual([3, -4]);
    expect(pairOf<readonly number[]>([[1, 2], [3, 4]], [])).toEqual([[1, 2], [3, 4]]);
  });

  it("reads a missing item as the stand-in, never as zero", () => {
    expect(numberPair([5])).toEqual([5, NaN]);
    expect(numberPair([])).toEqual([NaN, NaN]);
    expect(pairOf<readonly number[]>([[1, 2]], [])).toEqual([[1, 2], []]);
  });

  it("draws a point missing a coordinate nowhere (not at the origin)", () => {
    const [lat, lon] = fromMetres([36, -122], [100]);
    expect(Number.isNaN(lat)).toBe(true);
    expect(Number.isFinite(lon)).toBe(true);
  });
});
