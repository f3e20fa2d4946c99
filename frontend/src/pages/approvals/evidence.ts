/** What a recorded execution log evidenced, and what not, as one line of the record page. */
import type { Schema } from "../../api/client";

type Evidence = Schema<"EvidenceOut">;

export function evidenceText(evidence: Evidence | null | undefined): string {
  if (!evidence) return "evidence not checked (recorded before times and readings were required)";
  const shown = [
    evidence.timed ? "start and end times of every goal run" : null,
    evidence.constraints_read.length ? `readings for ${evidence.constraints_read.join(", ")}` : null,
  ].filter((part): part is string => part !== null);
  const evidenced = `evidenced: ${shown.length ? shown.join("; ") : "nothing"}`;
  return evidence.gaps.length ? `${evidenced}; not evidenced: ${evidence.gaps.join("; ")}` : evidenced;
}
