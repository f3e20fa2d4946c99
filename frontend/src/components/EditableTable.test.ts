import { createElement } from "react";
import { renderToStaticMarkup } from "react-dom/server";
import { describe, expect, it } from "vitest";

import type { Column } from "./DataTable";
import { EditableTable } from "./EditableTable";

type Limit = [string, number];

const columns: Column<Limit>[] = [
  { header: "Quantity", rowHeader: true, cell: ([q]) => q },
  { header: "Max", cell: ([q, max], i) => createElement("input", { "aria-label": `${q} max (row ${i + 1})`, defaultValue: max }) },
];

const html = (rows: Limit[], remove: Partial<Parameters<typeof EditableTable<Limit>>[0]["remove"]> = {}) =>
  renderToStaticMarkup(
    createElement(EditableTable<Limit>, {
      caption: "Limits",
      className: "limits",
      columns,
      rows,
      rowKey: ([q]) => q,
      remove: { header: "Remove", text: ([q]) => `Remove ${q}`, onRemove: () => undefined, ...remove },
    }),
  );

describe("EditableTable", () => {
  it("scrolls sideways inside its card rather than running past it (1024 px)", () => {
    expect(html([["depth_m", 50]])).toMatch(/^<div class="table-wrap"><table class="limits"/);
  });

  it("names each row by its row header and each input by the caller's label", () => {
    const out = html([["depth_m", 50]]);
    expect(out).toContain('<th scope="row">depth_m</th>');
    expect(out).toContain('aria-label="depth_m max (row 1)"');
    expect(out.match(/<th scope="col"/g)).toHaveLength(3);
  });

  it("ends each row with its remove button under a header read by screen readers only", () => {
    const out = html([["depth_m", 50]]);
    expect(out).toContain('<th scope="col"><span class="visually-hidden">Remove</span></th>');
    expect(out).toContain('<button type="button">Remove depth_m</button>');
  });

  it("gives a symbol-only button its accessible name", () => {
    const out = html([["depth_m", 50]], { text: () => "✕", label: ([q]) => `Delete quantity ${q}`, className: "small" });
    expect(out).toContain('<button type="button" class="small" aria-label="Delete quantity depth_m">✕</button>');
  });

  it("shows the caption when asked, and user text as text, never markup", () => {
    const shown = renderToStaticMarkup(
      createElement(EditableTable<Limit>, {
        caption: "Vertices of A",
        showCaption: true,
        className: "vertices",
        columns,
        rows: [["<b>x</b>", 1]],
        rowKey: (_, i) => i,
        remove: { header: "Remove", text: () => "✕", onRemove: () => undefined },
      }),
    );
    expect(shown).toContain("<caption>Vertices of A</caption>");
    expect(shown).toContain("&lt;b&gt;x&lt;/b&gt;");
    expect(shown).not.toContain("<b>");
  });
});
