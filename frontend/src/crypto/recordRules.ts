/**
 * The server's approval records against the log (in the browser): the log
 * is the source of truth, so a revocation or decision the log holds must have its record. A
 * database writer who deletes a revocation's `approvals` row makes the approval look valid;
 * here the log's `approval.revoked` entry still names it. Pure: events and rows in, problems out.
 */
export interface RecordEvent {
  kind?: string;
  mission?: unknown;
  detail?: Record<string, unknown>;
}

/** What the approvals list (GET /api/approvals) says of one record. */
export interface ApprovalRow {
  id: number;
  log_index: number | null;
  revokes: number | null;
}

/** Problems with the records of `mission` (`rows`, every record the server lists for it) and
 * of the approval `approvalId` shown, against the log's events (in log order). */
export function checkRecords(events: RecordEvent[], mission: string, approvalId: number, rows: ApprovalRow[]): string[] {
  const problems: string[] = [];
  const byIndex = new Map(rows.filter((r) => r.log_index !== null).map((r) => [r.log_index!, r]));
  const revokers = new Set(rows.filter((r) => r.revokes !== null).map((r) => r.revokes!));
  events.forEach((event, index) => {
    const kind = String(event.kind ?? "");
    const detail = event.detail ?? {};
    if (kind === "approval.revoked" && detail.revokes === approvalId && !revokers.has(approvalId)) {
      problems.push(
        `log entry ${index} revokes approval ${approvalId}, but the server shows it as not revoked: it is revoked (its revocation's approvals row was removed?)`,
      );
    }
    if (kind.startsWith("approval.") && event.mission === mission && !byIndex.has(index)) {
      problems.push(`log entry ${index} records a signed decision (${kind}) on ${mission}, but the server has no approval record for it (its approvals row was removed?)`);
    }
  });
  return problems;
}
