/**
 * The procedures a version's orders use: each library version by name, version and
 * pinned digest, whether the library holds it and who approved it, and one verdict line saying
 * whether every one is an approved version. Nothing is shown for orders that use none.
 */
import { type Column, DataTable } from "../../components/DataTable";
import { ErrorMessage } from "../../components/Status";
import { shortDigest } from "../../format";
import { type ProcedureUses, useProcedureUses } from "../../api/versions";

type Use = ProcedureUses["procedures"][number];

const COLUMNS: Column<Use>[] = [
  { header: "Procedure", rowHeader: true, cell: (use) => use.name },
  { header: "Version", cell: (use) => use.version },
  { header: "Pinned digest", cell: (use) => (use.digest ? <code title={use.digest}>{shortDigest(use.digest)}</code> : "none pinned") },
  { header: "Approved by", cell: (use) => use.approved_by ?? (use.in_library ? "not approved" : "not in the library") },
];

export function ProcedureUsesSection({ mission, version }: { mission: string; version: number }) {
  const { data, error } = useProcedureUses(mission, version);
  if (error) return <ErrorMessage error={error} />;
  if (!data || data.procedures.length === 0) return null;
  return (
    <section aria-labelledby="procedures-title" data-testid="review-procedures">
      <h2 id="procedures-title">Procedures</h2>
      <p className={data.all_approved ? "verdict ok" : "verdict bad"} data-testid="procedures-verdict">
        {data.all_approved
          ? "Every procedure these orders use is a version a supervisor approved."
          : "Not every procedure these orders use is an approved version."}
        {data.truncated && " (More procedures are named than are listed here.)"}
      </p>
      <DataTable
        caption={`Procedures used by ${mission} v${version}`}
        showCaption
        columns={COLUMNS}
        rows={data.procedures}
        rowKey={(use) => `${use.name}@${use.version}@${use.digest ?? ""}`}
        rowAttributes={() => ({ "data-testid": "procedure-use" })}
      />
    </section>
  );
}
