/**
 * The one table of the app: a caption (for screen readers, or shown), column headers with
 * `scope="col"`, one row per item, and optionally summary rows (a total) after them. Columns say
 * how to draw a cell; the rows stay the caller's. A record's fields (a name a row, its value
 * beside it) are a table without column headers whose first column holds row headers.
 * Read-only lists use it as it is; editable tables through EditableTable (inputs in the cells,
 * a remove button per row). No other component draws a `<table>` (a shape test holds that).
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
  /** Counts and measures: right-aligned in figures of one width, so that digits line up. */
  numeric?: boolean;
  /** A `data-testid` on the column's cells, the same for every row or one of each row's own. */
  testId?: string | ((row: Row, index: number) => string | undefined);
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
  /** Rows that sum up the others (e.g. "Any violation" after each ending), drawn after them
   * with the same columns. */
  footer?: readonly Row[];
  /** False for a record's fields: no header row, the row headers name each value. */
  columnHeaders?: boolean;
  /** A `data-testid` on the `<table>`. */
  testId?: string;
}

const classes = (...names: (string | false | undefined)[]) => names.filter(Boolean).join(" ") || undefined;

function cellClass<Row>(column: Column<Row>): string | undefined {
  return classes(column.className, column.numeric && "numeric");
}

function HeaderRow<Row>({ columns }: { columns: Column<Row>[] }) {
  return (
    <tr>
      {columns.map((column, index) => (
        <th key={index} scope="col" className={cellClass(column)}>
          {column.hiddenHeader ? <span className="visually-hidden">{column.header}</span> : column.header}
        </th>
      ))}
    </tr>
  );
}

function Cells<Row>({ columns, row, at }: { columns: Column<Row>[]; row: Row; at: number }) {
  return columns.map((column, index) => {
    const Cell = column.rowHeader ? "th" : "td";
    const testId = typeof column.testId === "function" ? column.testId(row, at) : column.testId;
    return (
      <Cell key={index} scope={column.rowHeader ? "row" : undefined} className={cellClass(column)} data-testid={testId}>
        {column.cell(row, at)}
      </Cell>
    );
  });
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
  footer,
  columnHeaders = true,
  testId,
}: DataTableProps<Row>) {
  const table = (
    <table className={className} aria-busy={scroll ? undefined : busy} data-testid={testId}>
      <caption className={showCaption ? undefined : "visually-hidden"}>{caption}</caption>
      {columnHeaders && (
        <thead>
          <HeaderRow columns={columns} />
        </thead>
      )}
      <tbody>
        {rows.length === 0 && empty !== undefined && (
          <tr>
            <td colSpan={columns.length}>{empty}</td>
          </tr>
        )}
        {rows.map((row, at) => (
          <tr key={rowKey(row, at)} className={rowClassName?.(row)} {...rowAttributes?.(row)}>
            <Cells columns={columns} row={row} at={at} />
          </tr>
        ))}
      </tbody>
      {footer && footer.length > 0 && (
        <tfoot>
          {footer.map((row, at) => (
            <tr key={rowKey(row, rows.length + at)} className={rowClassName?.(row)} {...rowAttributes?.(row)}>
              <Cells columns={columns} row={row} at={rows.length + at} />
            </tr>
          ))}
        </tfoot>
      )}
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
