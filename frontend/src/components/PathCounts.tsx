import { plural } from "../format";
import { DataTable } from "./DataTable";

/** How many paths end at each terminal, as the paths tab and the review pages show it. */
export function PathCounts({
  count,
  byTerminal,
  testIdPrefix,
}: {
  count: number;
  byTerminal: Record<string, number>;
  testIdPrefix: string;
}) {
  return (
    <DataTable
      caption={`${plural(count, "path")} from the start goal to a terminal`}
      showCaption
      className="counts"
      rows={Object.entries(byTerminal)}
      rowKey={([terminal]) => terminal}
      columns={[
        { header: "Terminal", rowHeader: true, cell: ([terminal]) => terminal },
        {
          header: "Paths",
          numeric: true,
          cell: ([, n]) => n.toLocaleString("en-US"),
          testId: ([terminal]) => `${testIdPrefix}${terminal}`,
        },
      ]}
    />
  );
}
