/**
 * What each role may do in the browser (DESIGN.md, Users; docs/api.md, Roles). The server
 * enforces the same rules; the UI only hides what would be refused anyway.
 */

import { OPERATION_ROLES } from "./roles.gen";

/** Every role a signed-in user may hold: those admitted to `whoAmI`. */
export const ROLES = OPERATION_ROLES.whoAmI;
export type Role = (typeof ROLES)[number];

export type Action =
  | "createMission"
  | "importMission"
  | "editDraft"
  | "deleteDraft"
  | "createVersion"
  | "manageUsers"
  | "manageVehicles"
  | "readEvents"
  | "startCampaign"
  | "cancelCampaign";

/** The route behind each action: its roles are the server's (roles.gen.ts, from x-roles). */
export const ACTION_OPERATION = {
  createMission: "createMission",
  importMission: "importMission",
  editDraft: "updateDraft",
  deleteDraft: "deleteMission",
  createVersion: "createVersion",
  manageUsers: "createUser",
  manageVehicles: "putVehicle",
  readEvents: "listEvents",
  startCampaign: "startCampaign",
  cancelCampaign: "cancelCampaign",
} as const satisfies Record<Action, keyof typeof OPERATION_ROLES>;

export function can(role: string | null | undefined, action: Action): boolean {
  return !!role && (OPERATION_ROLES[ACTION_OPERATION[action]] as readonly string[]).includes(role);
}

export const ROLE_LABEL: Record<Role, string> = {
  operator: "Operator",
  supervisor: "Supervisor",
  auditor: "Auditor",
  admin: "Admin",
};
