/**
 * Findings as the editor lists them: errors before warnings, grouped by code; the
 * loop findings (G7, one per elementary cycle, often dozens over the same goals) merged into one
 * item per loop, i.e. per set of goals that cycles share (a strongly connected part of the
 * graph); subject lists longer than SUBJECTS_SHOWN are folded by the list that shows them.
 */
export interface FindingLike {
  code: string;
  severity: string;
  subjects: string[];
  message: string;
}

export interface FindingItem<F extends FindingLike> {
  key: string;
  code: string;
  severity: "error" | "warning";
  message: string;
  subjects: string[];
  /** The findings the item stands for (a loop: one per cycle). */
  findings: F[];
}

export interface FindingGroup<F extends FindingLike> {
  key: string;
  code: string;
  severity: "error" | "warning";
  items: FindingItem<F>[];
}

export const SUBJECTS_SHOWN = 6;

/** Loops: G7 findings whose goals overlap, merged (union-find over the goals). */
export function loopsOf<F extends FindingLike>(findings: F[]): { goals: string[]; findings: F[] }[] {
  const parent = new Map<string, string>();
  const root = (x: string): string => {
    let r = x;
    while (parent.get(r) !== r) r = parent.get(r)!;
    parent.set(x, r);
    return r;
  };
  const cycles = findings.filter((f) => f.code === "G7" && f.subjects.length > 0);
  for (const f of cycles) {
    for (const s of f.subjects) if (!parent.has(s)) parent.set(s, s);
    const first = root(f.subjects[0]!);
    for (const s of f.subjects.slice(1)) parent.set(root(s), first);
  }
  const loops = new Map<string, { goals: string[]; findings: F[]; seen: Set<string> }>();
  for (const f of cycles) {
    const r = root(f.subjects[0]!);
    const loop = loops.get(r) ?? loops.set(r, { goals: [], findings: [], seen: new Set() }).get(r)!;
    loop.findings.push(f);
    for (const s of f.subjects) {
      if (!loop.seen.has(s)) {
        loop.seen.add(s);
        loop.goals.push(s);
      }
    }
  }
  return [...loops.values()].map(({ goals, findings: fs }) => ({ goals, findings: fs }));
}

export function groupFindings<F extends FindingLike>(findings: F[]): FindingGroup<F>[] {
  const groups = new Map<string, FindingGroup<F>>();
  const groupOf = (code: string, severity: "error" | "warning") => {
    const key = `${severity}:${code}`;
    return groups.get(key) ?? groups.set(key, { key, code, severity, items: [] }).get(key)!;
  };
  const loops = loopsOf(findings);
  const loopOf = new Map<F, number>();
  loops.forEach((l, i) => l.findings.forEach((f) => loopOf.set(f, i)));
  const placed = new Set<number>();
  findings.forEach((f, i) => {
    const severity = f.severity === "error" ? "error" : "warning";
    const loop = loopOf.get(f);
    if (loop !== undefined) {
      if (placed.has(loop)) return;
      placed.add(loop);
      const { goals, findings: cycles } = loops[loop]!;
      const worst = cycles.some((c) => c.severity === "error") ? "error" : "warning";
      groupOf(f.code, worst).items.push({
        key: `loop-${loop}`,
        code: f.code,
        severity: worst,
        message:
          cycles.length === 1
            ? f.message
            : `Loop through ${goals.length} goals: ${cycles.length} cycles share them (each cycle is a path back to a goal already run).`,
        subjects: goals,
        findings: cycles,
      });
      return;
    }
    groupOf(f.code, severity).items.push({ key: `f-${i}`, code: f.code, severity, message: f.message, subjects: f.subjects, findings: [f] });
  });
  const all = [...groups.values()];
  return [...all.filter((g) => g.severity === "error"), ...all.filter((g) => g.severity !== "error")];
}
