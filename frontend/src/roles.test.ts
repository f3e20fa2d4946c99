import { describe, expect, it } from "vitest";

import openapi from "../openapi.json";
import { ACTION_OPERATION, can, ROLES } from "./roles";

interface Operation {
  operationId: string;
  "x-roles"?: string[];
}

/** x-roles by operationId, read from the committed OpenAPI document (the server's routes). */
function serverRoles(): Map<string, string[]> {
  const document: { paths: Record<string, Record<string, Operation>> } = openapi;
  const table = new Map<string, string[]>();
  for (const operations of Object.values(document.paths)) {
    for (const operation of Object.values(operations)) table.set(operation.operationId, operation["x-roles"] ?? []);
  }
  return table;
}

describe("roles", () => {
  it("allow each action to exactly the roles its route admits", () => {
    const table = serverRoles();
    for (const [action, operation] of Object.entries(ACTION_OPERATION)) {
      const admitted = table.get(operation);
      expect(admitted, operation).toBeDefined();
      for (const role of [...ROLES, "anonymous"]) {
        expect(can(role, action as keyof typeof ACTION_OPERATION), `${action} as ${role}`).toBe(admitted!.includes(role));
      }
    }
  });

  it("list every role a signed-in user may hold", () => {
    expect([...ROLES]).toEqual(serverRoles().get("whoAmI"));
  });
});
