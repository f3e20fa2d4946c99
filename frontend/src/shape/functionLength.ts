/**
 * Function length measured with the TypeScript compiler's own parser: every function,
 * arrow function and method, its lines from the first to the last, blank lines and lines
 * holding only a comment left out (as eslint's max-lines-per-function with skipBlankLines and
 * skipComments counts). A nested function's lines count in its parent too. A function may
 * be longer when a comment just above it says why ("// Length: one table of ten columns").
 */
import ts from "typescript";

export interface FunctionLength {
  /** "src/editor/store.ts:createEditorStore"; an anonymous function is named by where it sits. */
  name: string;
  lines: number;
  /** The function's first line (1-based), for the failure message. */
  line: number;
  /** The reason given in a comment "Length: why" just above the function, or null. */
  reason: string | null;
}

/** A "Length: why" comment leading the function or the statement it sits in. */
function reasonOf(node: ts.Node, source: ts.SourceFile): string | null {
  for (let at: ts.Node | undefined = node; at && !ts.isSourceFile(at); at = at.parent) {
    for (const range of ts.getLeadingCommentRanges(source.text, at.getFullStart()) ?? []) {
      const found = /Length:\s*(.+)/.exec(source.text.slice(range.pos, range.end));
      if (found?.[1]) return found[1].replace(/\*\/$/, "").trim();
    }
    if (ts.isStatement(at) || ts.isClassElement(at)) break;
  }
  return null;
}

function nameOf(node: ts.Node): string | null {
  if ((ts.isFunctionDeclaration(node) || ts.isMethodDeclaration(node) || ts.isFunctionExpression(node)) && node.name) {
    return node.name.getText();
  }
  const parent = node.parent;
  if (ts.isVariableDeclaration(parent) || ts.isPropertyAssignment(parent) || ts.isPropertyDeclaration(parent)) {
    return parent.name.getText();
  }
  return null;
}

/** The lines of `text` that count: neither blank nor a comment alone. */
function countedLines(source: ts.SourceFile): boolean[] {
  const counted = source.text.split("\n").map((l) => l.trim() !== "");
  // Comments found by scanning: a line counts only if it holds something besides comments.
  const scanner = ts.createScanner(ts.ScriptTarget.Latest, false, source.languageVariant, source.text);
  const code = new Array<boolean>(counted.length).fill(false);
  for (let kind = scanner.scan(); kind !== ts.SyntaxKind.EndOfFileToken; kind = scanner.scan()) {
    const comment = kind === ts.SyntaxKind.SingleLineCommentTrivia || kind === ts.SyntaxKind.MultiLineCommentTrivia;
    if (comment || kind === ts.SyntaxKind.WhitespaceTrivia || kind === ts.SyntaxKind.NewLineTrivia) continue;
    const first = source.getLineAndCharacterOfPosition(scanner.getTokenStart()).line;
    const last = source.getLineAndCharacterOfPosition(scanner.getTokenEnd()).line;
    for (let l = first; l <= last; l++) code[l] = true;
  }
  return counted.map((c, i) => c && code[i] === true);
}

/** Every function in one file with its counted length. */
export function functionLengths(path: string, text: string): FunctionLength[] {
  const kind = path.endsWith(".tsx") ? ts.ScriptKind.TSX : ts.ScriptKind.TS;
  const source = ts.createSourceFile(path, text, ts.ScriptTarget.Latest, true, kind);
  const counted = countedLines(source);
  const found: FunctionLength[] = [];
  // An anonymous function inside one whose length has a reason (a store's body, an effect) is
  // covered by that reason: it is the part that makes its parent long.
  const visit = (node: ts.Node, outer: string, outerReason: string | null) => {
    let here = outer;
    let reason = outerReason;
    if (ts.isFunctionLike(node) && "body" in node && node.body) {
      const own = nameOf(node);
      here = own ?? `${outer || "(top)"}>anonymous`;
      const first = source.getLineAndCharacterOfPosition(node.getStart()).line;
      const last = source.getLineAndCharacterOfPosition(node.getEnd()).line;
      const lines = counted.slice(first, last + 1).filter(Boolean).length;
      reason = reasonOf(node, source) ?? (own === null ? outerReason : null);
      found.push({ name: `${path}:${here}`, lines, line: first + 1, reason });
    }
    ts.forEachChild(node, (child) => visit(child, here, reason));
  };
  visit(source, "", null);
  return found;
}
