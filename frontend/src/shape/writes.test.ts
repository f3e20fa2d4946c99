/**
 * Every write to the server goes through a mutation hook of its resource module (src/api/), so
 * the hook's onSuccess keeps the query cache true and no page re-fetches by hand.
 */
import { describe, expect, it } from "vitest";

import { writeBreaches } from "./writes";

// Every source file of the app, read as text by Vite; the tests and the generated API types are not app code.
const SOURCES = import.meta.glob(["../**/*.ts", "../**/*.tsx", "!../**/*.test.ts", "!../**/*.d.ts"], {
  query: "?raw",
  import: "default",
  eager: true,
}) as Record<string, string>;

// Parsing every file takes seconds on a loaded machine: a bound on a hang, not on speed.
const PARSE_TIMEOUT_MS = 120_000;

const breaches = (files: Record<string, string>) => writeBreaches(files).map((b) => `${b.at} ${b.what}`);

describe("writes go through mutation hooks", () => {
  it("holds for the app", () => {
    const app = Object.fromEntries(Object.entries(SOURCES).map(([path, text]) => [`src/${path.slice(3)}`, text]));
    expect(Object.keys(app).length).toBeGreaterThan(50);
    expect(breaches(app)).toEqual([]);
  }, PARSE_TIMEOUT_MS);

  it("finds a component that writes by itself", () => {
    const page = 'const save = async () => unwrap(await api.PUT("/api/vehicles/{vehicle_id}", { body }));';
    expect(breaches({ "src/pages/Page.tsx": page })).toEqual(["src/pages/Page.tsx:1 PUT /api/vehicles/{vehicle_id} outside a mutation hook of src/api/"]);
    const raw = 'fetch("/api/tokens/1", { method: "DELETE" });\nfetch("/land.json");';
    expect(breaches({ "src/pages/Page.tsx": raw })).toEqual(["src/pages/Page.tsx:1 fetch with method DELETE outside a mutation hook of src/api/"]);
  });

  it("finds a write helper of an api module called from an event handler", () => {
    const module = [
      'export async function saveVehicle(p) { unwrap(await api.PUT("/api/vehicles/{vehicle_id}", { body: p })); }',
      "export function useSaveVehicle() { return useMutation({ mutationFn: saveVehicle, onSuccess: () => vehicleSaved(client) }); }",
    ].join("\n");
    expect(breaches({ "src/api/vehicles.ts": module })).toEqual([]);
    const page = 'import { saveVehicle } from "../api/vehicles";\nconst onClick = () => saveVehicle(profile);';
    expect(breaches({ "src/api/vehicles.ts": module, "src/pages/V.tsx": page })).toEqual([
      "src/pages/V.tsx:1 saveVehicle (PUT /api/vehicles/{vehicle_id}) used outside a mutationFn",
      "src/pages/V.tsx:2 saveVehicle (PUT /api/vehicles/{vehicle_id}) used outside a mutationFn",
    ]);
  });

  it("finds a mutationFn called by hand, which would skip onSuccess", () => {
    const page = "await submissionMutation(client, mission).mutationFn({ submit: 1 });";
    expect(breaches({ "src/pages/P.tsx": page })).toEqual(["src/pages/P.tsx:1 a mutationFn called by hand (use the mutation hook)"]);
  });

  it("lets a POST that stores nothing be called where it is needed", () => {
    expect(breaches({ "src/api/reports.ts": 'export const check = (o) => api.POST("/api/validate", { body: o });' })).toEqual([]);
  });
});
