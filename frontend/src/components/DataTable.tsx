/**
 * The one table of the app: a caption (for screen readers, or shown), column headers with
 * `scope="col"`, one row per item. Columns say how to draw a cell; the rows stay the caller's.
 * Read-only lists use it as it is; editable tables through EditableTable (inputs in the cells,
 * a remove button per row).
 */
import type { ReactNode } from "react";

export interface Column<Row> {
  /** The header's text. */
  header: ReactNode;
  /** The header is read by screen readers only (a column of buttons needs no visible one). */
  hiddenHeader?: boolean;
  /** The cell names its row (`<th scope="row">`), e.g. the quantity a row of limits is of. */
  rowHeader?: boolean;
  cell: (row: Row, index: number) => ReactNode;
  /** A class on the column's cells (widths and alignment live in the stylesheet). */
  className?: string;
  /** A `data-testid` on the column's cells. */
  testId?: string;
}

/** Attributes of a row's `<tr>` beyond its key and class (e.g. `data-testid`). */
export type RowAttributes = Record<`data-${string}`, string>;

export interface DataTableProps<Row> {
  /** What the table lists, read out by screen readers (visually hidden unless `showCaption`). */
  caption: string;
  showCaption?: boolean;
  columns: Column<Row>[];
  rows: readonly Row[];
  rowKey: (row: Row, index: number) => string | number;
  /** The table's own class, for the stylesheet's rules of that list. */
  className?: string;
  rowClassName?: (row: Row) => string | undefined;
  rowAttributes?: (row: Row) => RowAttributes;
  /** True while newer rows are being fetched (the old ones stay shown). */
  busy?: boolean;
  /** Wrap in a horizontally scrolling box (wide tables on narrow screens). */
  scroll?: boolean;
  /** Said in one full-width row when there are no rows (else the table is empty). */
  empty?: ReactNode;
}

export function DataTable<Row>({
  caption,
  showCaption,
  columns,
  rows,
  rowKey,
  className,
  rowClassName,
  rowAttributes,
  busy,
  scroll,
  empty,
}: DataTableProps<Row>) {
  const table = (
    <table className={className} aria-busy={scroll ? undefined : busy}>
      <caption className={showCaption ? undefined : "visually-hidden"}>{caption}</caption>
      <thead>
        <tr>
          {columns.map((column, index) => (
            <th key={index} scope="col" className={column.className}>
              {column.hiddenHeader ? <span className="visually-hidden">{column.header}</span> : column.header}
            </th>
          ))}
        </tr>
      </thead>
      <tbody>
        {rows.length === 0 && empty !== undefined && (
          <tr>
            <td colSpan={columns.length}>{empty}</td>
          </tr>
        )}
        {rows.map((row, at) => (
          <tr key={rowKey(row, at)} className={rowClassName?.(row)} {...rowAttributes?.(row)}>
            {columns.map((column, index) => {
              const Cell = column.rowHeader ? "th" : "td";
              return (
                <Cell key={index} scope={column.rowHeader ? "row" : undefined} className={column.className} data-testid={column.testId}>
                  {column.cell(row, at)}
                </Cell>
              );
            })}
          </tr>
        ))}
      </tbody>
    </table>
  );
  return scroll ? (
    <div className="table-wrap" aria-busy={busy}>
      {table}
    </div>
  ) : (
    table
  );
}
