/**
 * Where the app writes to the server. A write is a request with a state-changing method
 * (`api.POST`, `PUT`, `PATCH`, `DELETE`, or `fetch` with such a `method`), except the few POST
 * routes that only compute an answer and store nothing (READS_BY_POST). The rule: a write is
 * sent from a mutation's `mutationFn` in a resource module (src/api/), directly or through a
 * helper of that module that only `mutationFn`s call, so that the mutation's `onSuccess` keeps
 * the query cache true; nothing else calls a `mutationFn` by hand.
 */
import ts from "typescript";

/** POST routes that answer without changing anything on the server, each with why. */
export const READS_BY_POST: Record<string, string> = {
  "/api/read": "reads an uploaded file into orders; nothing is stored",
  "/api/validate": "checks orders not yet saved; the report is cached by digest, nothing else is stored",
  "/api/plan-view": "draws the plan of the orders sent",
  "/api/plan": "solves the planning problem sent",
  "/api/missions/{mission_id}/plan-problem": "builds a planning problem from the saved draft's areas",
};

const WRITE_METHODS = new Set(["POST", "PUT", "PATCH", "DELETE"]);

export interface WriteBreach {
  /** "src/pages/X.tsx:12" */
  at: string;
  what: string;
}

interface Source {
  path: string;
  file: ts.SourceFile;
}

const isApiModule = (path: string) => path.startsWith("src/api/");

function parse(path: string, text: string): Source {
  const kind = path.endsWith(".tsx") ? ts.ScriptKind.TSX : ts.ScriptKind.TS;
  return { path, file: ts.createSourceFile(path, text, ts.ScriptTarget.Latest, true, kind) };
}

function where(source: Source, node: ts.Node): string {
  return `${source.path}:${source.file.getLineAndCharacterOfPosition(node.getStart()).line + 1}`;
}

function each(node: ts.Node, visit: (node: ts.Node) => void): void {
  visit(node);
  ts.forEachChild(node, (child) => each(child, visit));
}

/** The route and method of `api.POST("/route", ...)` or `fetch(url, { method: "POST" })`, if it writes. */
function writeOf(node: ts.Node): string | null {
  if (!ts.isCallExpression(node)) return null;
  const callee = node.expression;
  if (ts.isPropertyAccessExpression(callee) && callee.expression.getText() === "api" && WRITE_METHODS.has(callee.name.text)) {
    const route = node.arguments[0];
    const path = route && ts.isStringLiteralLike(route) ? route.text : "(a computed route)";
    return callee.name.text === "POST" && path in READS_BY_POST ? null : `${callee.name.text} ${path}`;
  }
  if (ts.isIdentifier(callee) && callee.text === "fetch") {
    const options = node.arguments[1];
    if (!options || !ts.isObjectLiteralExpression(options)) return null;
    const method = options.properties.find((p) => p.name?.getText() === "method");
    if (!method) return null;
    const value = ts.isPropertyAssignment(method) && ts.isStringLiteralLike(method.initializer) ? method.initializer.text.toUpperCase() : "(computed)";
    return value === "GET" || value === "HEAD" ? null : `fetch with method ${value}`;
  }
  return null;
}

/** Whether `node` sits in the value of a `mutationFn:` property (or is that value). */
function inMutationFn(node: ts.Node): boolean {
  for (let at: ts.Node | undefined = node; at && !ts.isSourceFile(at); at = at.parent) {
    if ((ts.isPropertyAssignment(at) || ts.isShorthandPropertyAssignment(at)) && at.name.getText() === "mutationFn") return true;
  }
  return false;
}

/** The name of the top-level function `node` is in (`function f` or `const f = () => ...`). */
function topLevelName(node: ts.Node): string | null {
  let at: ts.Node = node;
  while (at.parent && !ts.isSourceFile(at.parent)) at = at.parent;
  if (ts.isFunctionDeclaration(at) && at.name) return at.name.text;
  if (ts.isVariableStatement(at)) {
    const declaration = at.declarationList.declarations[0];
    if (declaration && ts.isIdentifier(declaration.name)) return declaration.name.text;
  }
  return null;
}

/** Every write sent outside a mutation, and every call of a write helper or of a `mutationFn`
 * outside one. `sources` maps "src/..." paths to their text (tests and type files left out). */
export function writeBreaches(sources: Record<string, string>): WriteBreach[] {
  const parsed = Object.entries(sources).map(([path, text]) => parse(path, text));
  const breaches: WriteBreach[] = [];
  const helpers = new Map<string, string>();
  for (const source of parsed) {
    each(source.file, (node) => {
      const write = writeOf(node);
      if (!write || inMutationFn(node)) return;
      const helper = isApiModule(source.path) ? topLevelName(node) : null;
      if (helper) helpers.set(helper, write);
      else breaches.push({ at: where(source, node), what: `${write} outside a mutation hook of src/api/` });
    });
  }
  for (const source of parsed) {
    each(source.file, (node) => {
      if (ts.isPropertyAccessExpression(node) && node.name.text === "mutationFn") {
        breaches.push({ at: where(source, node), what: "a mutationFn called by hand (use the mutation hook)" });
      }
      if (!ts.isIdentifier(node) || !helpers.has(node.text) || inMutationFn(node)) return;
      const parent = node.parent;
      const declares = (ts.isFunctionDeclaration(parent) || ts.isVariableDeclaration(parent)) && parent.name === node;
      if (!declares) breaches.push({ at: where(source, node), what: `${node.text} (${helpers.get(node.text)}) used outside a mutationFn` });
    });
  }
  return breaches;
}
