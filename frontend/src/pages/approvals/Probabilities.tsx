/** The review's outcome probabilities: what the supervisor signs with the orders. */
import { DataTable } from "../../components/DataTable";
import { type OutcomeFigures, probabilityRows } from "./probabilities";

export function ProbabilityTable({ figures }: { figures: OutcomeFigures | null | undefined }) {
  if (!figures) return null;
  const rows = probabilityRows(figures);
  return (
    <>
      <h2>Outcome probabilities</h2>
      <p className="hint">
        {figures.exact
          ? "Exact, from the outcome probabilities in the orders; these figures are inside the signed statement."
          : `Bounds: ${[...figures.intervals, ...figures.unknown].join(", ")} give intervals or no probabilities.`}
      </p>
      <DataTable
        caption="Outcome probabilities"
        testId="review-probabilities"
        columnHeaders={false}
        rows={rows}
        rowKey={(row) => row.what}
        columns={[
          { header: "Outcome", rowHeader: true, cell: (row) => row.what },
          { header: "Probability", cell: (row) => row.value },
        ]}
      />
    </>
  );
}
