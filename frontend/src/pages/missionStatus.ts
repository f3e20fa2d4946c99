/** The mission page's status in words with its standing: a rejection of v2
 * does not hide that v1 stands approved, so the status never says only "Rejected" then. */
import { statusLabel } from "../format";

export interface Decided {
  version: number;
  decision: string;
  record: number;
}

export function statusWords(status: string, approved: Decided | null | undefined, latest: Decided | null | undefined): string {
  const label = statusLabel(status);
  if (!approved) return label;
  const later = latest && latest.record !== approved.record ? `v${latest.version} ${latest.decision}` : null;
  if (status === "approved") return `Approved (v${approved.version})`;
  if (status === "rejected" || status === "revoked") return `v${approved.version} approved; ${later ?? label.toLowerCase()}`;
  return `${label}; v${approved.version} approved`;
}
