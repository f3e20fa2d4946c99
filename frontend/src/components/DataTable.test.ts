import { createElement } from "react";
import { renderToStaticMarkup } from "react-dom/server";
import { describe, expect, it } from "vitest";

import { type Column, DataTable } from "./DataTable";

interface Row {
  id: number;
  name: string;
}

const columns: Column<Row>[] = [
  { header: "Id", cell: (r) => r.id },
  { header: "Name", cell: (r) => r.name, testId: "row-name" },
];

const html = (props: Partial<Parameters<typeof DataTable<Row>>[0]> & { rows: Row[] }) =>
  renderToStaticMarkup(createElement(DataTable<Row>, { caption: "People", columns, rowKey: (r) => r.id, ...props }));

describe("DataTable", () => {
  it("has a caption and column headers with scope", () => {
    const out = html({ rows: [{ id: 1, name: "Ann" }] });
    expect(out).toContain('<caption class="visually-hidden">People</caption>');
    expect(out.match(/<th scope="col"/g)).toHaveLength(2);
    expect(out).toContain('<td data-testid="row-name">Ann</td>');
  });

  it("shows user text as text, never markup", () => {
    const out = html({ rows: [{ id: 1, name: "<img src=x onerror=alert(1)>" }] });
    expect(out).not.toContain("<img");
    expect(out).toContain("&lt;img src=x onerror=alert(1)&gt;");
  });

  it("says when it is empty, across every column", () => {
    expect(html({ rows: [], empty: "Nobody yet." })).toMatch(/<td colspan="2">Nobody yet.<\/td>/i);
    expect(html({ rows: [] })).not.toContain("<td");
  });

  it("puts row attributes and busy on the scrolling box", () => {
    const out = html({ rows: [{ id: 7, name: "B" }], scroll: true, busy: true, rowAttributes: () => ({ "data-testid": "person" }) });
    expect(out).toMatch(/^<div class="table-wrap" aria-busy="true"><table>/);
    expect(out).toContain('<tr data-testid="person">');
  });

  it("aligns numeric columns, header and cells alike", () => {
    const numeric: Column<Row>[] = [{ header: "Id", numeric: true, className: "id", cell: (r) => r.id }];
    const out = html({ rows: [{ id: 3, name: "C" }], columns: numeric });
    expect(out).toContain('<th scope="col" class="id numeric">Id</th>');
    expect(out).toContain('<td class="id numeric">3</td>');
  });

  it("gives each row's cell a test id of its own", () => {
    const own: Column<Row>[] = [{ header: "Name", rowHeader: true, cell: (r) => r.name, testId: (r) => `person-${r.id}` }];
    const out = html({ rows: [{ id: 1, name: "Ann" }, { id: 2, name: "Bo" }], columns: own });
    expect(out).toContain('<th scope="row" data-testid="person-1">Ann</th>');
    expect(out).toContain('<th scope="row" data-testid="person-2">Bo</th>');
  });

  it("draws summary rows after the others, with the same columns", () => {
    const out = html({ rows: [{ id: 1, name: "Ann" }], footer: [{ id: 0, name: "Everyone" }] });
    expect(out).toMatch(/<\/tbody><tfoot><tr><td>0<\/td><td data-testid="row-name">Everyone<\/td><\/tr><\/tfoot><\/table>$/);
    expect(html({ rows: [], footer: [] })).not.toContain("<tfoot");
  });

  it("draws a record's fields without a header row, named by a test id", () => {
    const out = html({ rows: [{ id: 1, name: "Ann" }], columnHeaders: false, testId: "person" });
    expect(out).toMatch(/^<table data-testid="person"><caption/);
    expect(out).not.toContain("<thead");
    expect(out).not.toContain('scope="col"');
  });
});
