/** Issue 14 finding 6 in the browser's verifier: the shared vectors (also run by
 * tests/api/test_duty_rules.py against the Python rule), and checkLog carrying the rule. */
import { describe, expect, it } from "vitest";

import vectors from "./__fixtures__/duties.json";
import { checkDuties, type DutyEvent } from "./dutyRules";
import { checkLog } from "./logRules";

describe("separation of duties from the log", () => {
  for (const c of vectors.cases) {
    it(c.name, () => {
      expect(checkDuties(c.events as DutyEvent[])).toEqual(c.problems);
    });
  }

  it("is one of the log-wide rules (finding 6: edit, promotion, approval)", () => {
    const c = vectors.cases[0]!;
    expect(checkLog(c.events as DutyEvent[])).toEqual(c.problems);
  });
});
