import { describe, expect, it } from "vitest";

import { packageHref, vehicleFileHref } from "./VehicleExports";

describe("vehicle file links", () => {
  it("name the version, format and file, escaped", () => {
    expect(vehicleFileHref("a b", 3, "moos", "a b.bhv")).toBe(
      "/api/missions/a%20b/versions/3/vehicle/moos/a%20b.bhv",
    );
  });

  it("link the approved package of a version", () => {
    expect(packageHref("m/x", 2)).toBe("/api/missions/m%2Fx/versions/2/package");
  });
});
