/**
 * Where the app draws a table of its own. DataTable (src/components/DataTable.tsx) is the one
 * table component: captions, header scopes, empty rows and scrolling are decided there once, so
 * every other component hands it columns and rows instead of writing `<table>` markup (in JSX
 * or through `createElement("table")`).
 */
import ts from "typescript";

export const TABLE_COMPONENT = "src/components/DataTable.tsx";

export interface TableBreach {
  /** "src/pages/X.tsx:12" */
  at: string;
}

function drawsTable(node: ts.Node): boolean {
  if (ts.isJsxOpeningElement(node) || ts.isJsxSelfClosingElement(node)) return node.tagName.getText() === "table";
  if (!ts.isCallExpression(node)) return false;
  const callee = node.expression;
  const name = ts.isPropertyAccessExpression(callee) ? callee.name.text : ts.isIdentifier(callee) ? callee.text : "";
  const tag = node.arguments[0];
  return name === "createElement" && tag !== undefined && ts.isStringLiteralLike(tag) && tag.text === "table";
}

/** Every `<table>` drawn outside DataTable. `sources` maps "src/..." paths to their text. */
export function tableBreaches(sources: Record<string, string>): TableBreach[] {
  const breaches: TableBreach[] = [];
  for (const [path, text] of Object.entries(sources)) {
    if (path === TABLE_COMPONENT) continue;
    const kind = path.endsWith(".tsx") ? ts.ScriptKind.TSX : ts.ScriptKind.TS;
    const file = ts.createSourceFile(path, text, ts.ScriptTarget.Latest, true, kind);
    const visit = (node: ts.Node): void => {
      if (drawsTable(node)) breaches.push({ at: `${path}:${file.getLineAndCharacterOfPosition(node.getStart()).line + 1}` });
      ts.forEachChild(node, visit);
    };
    visit(file);
  }
  return breaches;
}
