import type { Finding } from "../api/client";
import { type Column, DataTable } from "./DataTable";

const COLUMNS: Column<Finding>[] = [
  { header: "Code", cell: (f) => <code>{f.code}</code> },
  { header: "Severity", cell: (f) => <span className={`badge ${f.severity === "error" ? "bad" : "warn"}`}>{f.severity}</span> },
  { header: "Subjects", cell: (f) => f.subjects.join(", ") },
  { header: "Message", cell: (f) => f.message },
];

/** The findings of a validation report, as the findings tab and the review pages list them. */
export function FindingsTable({ findings, caption }: { findings: Finding[]; caption: string }) {
  if (findings.length === 0) return <p className="empty">No findings.</p>;
  return (
    <DataTable
      caption={caption}
      className="findings"
      columns={COLUMNS}
      rows={findings}
      rowKey={(f, i) => `${f.code}-${i}`}
      rowClassName={(f) => `severity-${f.severity}`}
      scroll
    />
  );
}
