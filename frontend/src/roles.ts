/**
 * What each role may do in the browser (DESIGN.md, Users; docs/api.md, Roles). The server
 * enforces the same rules; the UI only hides what would be refused anyway.
 */

export type Role = "operator" | "supervisor" | "auditor" | "admin";

export type Action =
  | "createMission"
  | "importMission"
  | "editDraft"
  | "deleteDraft"
  | "createVersion"
  | "manageUsers"
  | "manageVehicles"
  | "readEvents";

const ALLOWED: Record<Action, readonly Role[]> = {
  createMission: ["operator"],
  importMission: ["operator"],
  editDraft: ["operator"],
  deleteDraft: ["operator"],
  createVersion: ["operator"],
  manageUsers: ["admin"],
  manageVehicles: ["admin"],
  readEvents: ["auditor", "supervisor", "admin"],
};

export function can(role: string | null | undefined, action: Action): boolean {
  return !!role && (ALLOWED[action] as readonly string[]).includes(role);
}

export const ROLES: readonly Role[] = ["operator", "supervisor", "auditor", "admin"];

export const ROLE_LABEL: Record<Role, string> = {
  operator: "Operator",
  supervisor: "Supervisor",
  auditor: "Auditor",
  admin: "Admin",
};
