/** The side column's findings: the verdict of the newest check and the findings of the scope. */
import type { Finding } from "../api/client";
import { plural } from "../format";
import { FindingsList } from "./Inspector";
import { useEditor } from "./store";

export function FindingsPanel({ findings, onPick }: { findings: Finding[]; onPick: (f: Finding, given?: string[]) => void }) {
  const report = useEditor((s) => s.report);
  const refusal = useEditor((s) => s.refusal);
  const checkMs = useEditor((s) => s.checkMs);
  const errors = findings.filter((f) => f.severity === "error").length;
  // Inside a refinement or a team member the list holds that scope's findings, while the
  // verdict is the whole mission's: say where its other errors are, or "Not valid: 0 errors"
  // reads as a contradiction.
  const elsewhere = (report?.findings ?? []).filter((f) => f.severity === "error").length - errors;
  return (
    <section className="editor-findings-panel" aria-labelledby="editor-findings-title" tabIndex={0} data-testid="editor-findings-panel">
      <h3 id="editor-findings-title">Findings</h3>
      {report && (
        <p className={report.ok ? "verdict ok" : "verdict bad"} data-testid="editor-verdict">
          {refusal ? "As last saved: " : ""}
          {report.ok ? "Valid" : "Not valid"}: {plural(errors, "error")}
          {elsewhere > 0 ? ` here (${elsewhere} elsewhere in the mission)` : ""}, {plural(findings.length - errors, "warning")}.
          {report.paths ? ` ${plural(report.paths.count, "path")}.` : ""}
          {checkMs !== null && <span className="hint" data-testid="check-time"> Checked {checkMs} ms after the edit.</span>}
        </p>
      )}
      <FindingsList findings={findings} onPick={onPick} refused={refusal?.message ?? null} />
    </section>
  );
}
