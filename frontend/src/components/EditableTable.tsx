/**
 * The one editable table: the caller's inputs in the cells (each with its own accessible
 * name) and, last, a button per row that removes it. It is a DataTable, so headers, captions
 * and row headers read the same in every table of the app.
 */
import type { ReactNode } from "react";

import { type Column, DataTable } from "./DataTable";

export interface RemoveColumn<Row> {
  /** The column's header, read by screen readers only ("Remove", "Delete"). */
  header: string;
  /** The button's text; with `label`, its accessible name instead (a "✕" says nothing). */
  text: (row: Row, index: number) => ReactNode;
  label?: (row: Row, index: number) => string;
  className?: string;
  onRemove: (row: Row, index: number) => void;
}

export interface EditableTableProps<Row> {
  caption: string;
  showCaption?: boolean;
  className: string;
  columns: Column<Row>[];
  rows: readonly Row[];
  rowKey: (row: Row, index: number) => string | number;
  remove: RemoveColumn<Row>;
}

function removeColumn<Row>(remove: RemoveColumn<Row>): Column<Row> {
  return {
    header: remove.header,
    hiddenHeader: true,
    cell: (row, index) => (
      <button type="button" className={remove.className} aria-label={remove.label?.(row, index)} onClick={() => remove.onRemove(row, index)}>
        {remove.text(row, index)}
      </button>
    ),
  };
}

/** Always in a horizontally scrolling box: its inputs keep a width a value can be read in,
 * so at 1024 px the Quantities table is wider than its card and scrolls inside it. */
export function EditableTable<Row>({ remove, columns, ...table }: EditableTableProps<Row>) {
  return <DataTable {...table} scroll columns={[...columns, removeColumn(remove)]} />;
}
