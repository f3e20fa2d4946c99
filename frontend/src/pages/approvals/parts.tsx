/** Pieces shared by the review and audit pages: findings, path summary, diff, state badge,
 * contingency rules. */
import { statusLabel } from "../../format";
import { DataTable } from "../../components/DataTable";
import { FindingsTable } from "../../components/FindingsTable";
import { PathCounts } from "../../components/PathCounts";
import type { PathSummary } from "./api";

export { FindingsTable };
import { type OrdersDiff, showValue } from "./diff";

export function StateBadge({ state }: { state: string }) {
  const tone = state === "approved" ? "ok" : state === "rejected" || state === "revoked" ? "bad" : state === "submitted" ? "warn" : "muted";
  return (
    <span className={`badge ${tone}`} data-testid="submission-state">
      {statusLabel(state)}
    </span>
  );
}

/** Where a row disagrees with the log (the source of truth): the server's `integrity` list,
 * shown as a warning so that the row's value is never taken as fact. */
export function IntegrityWarning({ problems }: { problems?: string[] | null }) {
  if (!problems || problems.length === 0) return null;
  return (
    <div className="message error" role="alert" data-testid="integrity-warning">
      <p>The database disagrees with the log; the log is what counts:</p>
      <ul>
        {problems.map((p) => (
          <li key={p}>{p}</li>
        ))}
      </ul>
    </div>
  );
}

/** The contingency rules (a normal default theory, seed 004) as the server words them, one
 * sentence per rule; they guide the vehicle when observations go wrong during the mission. */
export function RulesSection({ rules, headingLevel = 2 }: { rules: string[]; headingLevel?: 2 | 3 }) {
  const Heading = headingLevel === 2 ? "h2" : "h3";
  return (
    <section aria-labelledby="rules-title" data-testid="contingency-rules">
      <Heading id="rules-title">Contingency rules</Heading>
      {rules.length === 0 ? (
        <p className="empty">These orders and their vehicle carry no contingency rules.</p>
      ) : (
        <>
          <p className="hint">
            What the vehicle concludes and does when observations go wrong, one sentence per rule; a rule that says
            "normally" applies unless it contradicts what is known.
          </p>
          <ol className="rules">
            {rules.map((sentence, i) => (
              <li key={i}>{sentence}</li>
            ))}
          </ol>
        </>
      )}
    </section>
  );
}

export function PathSummaryTable({ paths }: { paths: PathSummary | null }) {
  if (!paths) return <p className="empty">The paths cannot be counted until the structural errors are fixed.</p>;
  return <PathCounts count={paths.count} byTerminal={paths.by_terminal} testIdPrefix="review-paths-to-" />;
}

export function DiffView({ diff }: { diff: OrdersDiff }) {
  if (diff.same) return <p className="empty">No differences: the orders are the same.</p>;
  const rows: { what: string; id: string; change: string; detail: string }[] = [];
  for (const f of diff.fields) {
    rows.push({ what: "Mission", id: f.field, change: "changed", detail: `${showValue(f.before)} → ${showValue(f.after)}` });
  }
  for (const s of diff.sections) {
    for (const a of s.added) rows.push({ what: s.label, id: a.label, change: "added", detail: "" });
    for (const r of s.removed) rows.push({ what: s.label, id: r.label, change: "removed", detail: "" });
    for (const c of s.changed) {
      rows.push({
        what: s.label,
        id: c.label,
        change: "changed",
        detail: c.fields.map((f) => `${f.field}: ${showValue(f.before, 80)} → ${showValue(f.after, 80)}`).join("; "),
      });
    }
  }
  return (
    <DataTable
      caption="Differences from the previously approved version"
      className="diff"
      testId="orders-diff"
      scroll
      rows={rows}
      rowKey={(_, i) => i}
      rowClassName={(r) => `diff-${r.change}`}
      columns={[
        { header: "Part", cell: (r) => r.what },
        { header: "Item", cell: (r) => <code>{r.id}</code> },
        {
          header: "Change",
          cell: (r) => <span className={`badge ${r.change === "added" ? "ok" : r.change === "removed" ? "bad" : "warn"}`}>{r.change}</span>,
        },
        { header: "Detail", cell: (r) => r.detail },
      ]}
    />
  );
}
