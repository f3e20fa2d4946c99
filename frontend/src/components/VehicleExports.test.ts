import { describe, expect, it } from "vitest";

import { vehicleFileHref } from "./VehicleExports";

describe("vehicle file links", () => {
  it("name the version, format and file, escaped", () => {
    expect(vehicleFileHref("a b", 3, "moos", "a b.bhv")).toBe(
      "/api/missions/a%20b/versions/3/vehicle/moos/a%20b.bhv",
    );
  });
});
