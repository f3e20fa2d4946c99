/**
 * Pure pieces of the editor's pickers: the choices a goal, behaviour or vehicle picker offers,
 * how typed text narrows them, and which keys only move through a native drop-down (so that
 * passing an option with the arrow keys does not save it).
 */

/** One option of a picker: `value` is stored, `label` shown (and searched), `detail` after it. */
export interface Choice {
  value: string;
  label: string;
  detail?: string;
}

/** At most this many choices are rendered at once; typing narrows the rest. */
export const CHOICES_SHOWN = 100;

/**
 * The choices whose label or value contains every word of `query` (case-insensitive), those
 * whose value starts with the query first; an empty query keeps them all, in order.
 */
export function filterChoices(choices: readonly Choice[], query: string): Choice[] {
  const words = query.trim().toLowerCase().split(/\s+/).filter(Boolean);
  if (words.length === 0) return [...choices];
  const text = (c: Choice) => `${c.value} ${c.label} ${c.detail ?? ""}`.toLowerCase();
  const found = choices.filter((c) => words.every((w) => text(c).includes(w)));
  const head = query.trim().toLowerCase();
  const starts = (c: Choice) => (c.value.toLowerCase().startsWith(head) ? 0 : 1);
  return found.map((c, i) => ({ c, i })).sort((a, b) => starts(a.c) - starts(b.c) || a.i - b.i).map((x) => x.c);
}

/** "G3: Survey the box" (or the id alone when untitled). */
export function idAndTitle(id: string, title?: string | null): string {
  return title && title.trim() ? `${id}: ${title}` : id;
}

type Titled = { id: string; title?: string | null };

/** The successor choices of a goal: no successor, then every goal and terminal by id + title. */
export function successorChoices(goals: readonly Titled[], terminals: readonly (Titled & { kind?: string })[]): Choice[] {
  return [
    { value: "", label: "— none —" },
    ...goals.map((g) => ({ value: g.id, label: idAndTitle(g.id, g.title), detail: "goal" })),
    ...terminals.map((t) => ({ value: t.id, label: idAndTitle(t.id, t.title), detail: t.kind ? `${t.kind} terminal` : "terminal" })),
  ];
}

/** A profile as far as its trusted behaviours go. */
export type BehaviourProfile = { behaviors?: readonly string[] | null; features?: readonly { fulfills?: readonly string[] | null }[] | null };

/** A vehicle's trusted behaviours (DESIGN.md, as M7 reads them): its `behaviors` list when it
 * gives a non-empty one, otherwise the behaviours its features fulfil. */
export function trustedBehaviours(profile: BehaviourProfile): string[] {
  const listed = profile.behaviors ?? [];
  const source = listed.length > 0 ? listed : (profile.features ?? []).flatMap((f) => f.fulfills ?? []);
  return [...new Set(source)];
}

/** A behaviour picker's choices: the vehicle's trusted behaviours, the current value marked when
 * it is not one of them. */
export function behaviourChoices(trusted: readonly string[], current: string | undefined, vehicle: string | undefined): Choice[] {
  const list: Choice[] = [{ value: "", label: "— none —" }];
  for (const b of trusted) list.push({ value: b, label: b, detail: vehicle ? `trusted by ${vehicle}` : undefined });
  if (current && !trusted.includes(current)) {
    list.push({ value: current, label: current, detail: vehicle ? `not a trusted behaviour of ${vehicle}` : "no vehicle profile" });
  }
  return list;
}

/**
 * Keys that, on a focused closed native <select>, change its value at once (Chromium and
 * Firefox fire "change" for each): they only move through the options, so the editor keeps the
 * choice pending until Enter, a click or focus leaving the field.
 */
export function movesThroughOptions(key: string, modifiers: { altKey?: boolean; ctrlKey?: boolean; metaKey?: boolean } = {}): boolean {
  if (modifiers.altKey || modifiers.ctrlKey || modifiers.metaKey) return false; // Alt+Down opens the list
  if (["ArrowUp", "ArrowDown", "ArrowLeft", "ArrowRight", "Home", "End", "PageUp", "PageDown"].includes(key)) return true;
  return key.length === 1 && key !== " "; // type-ahead jumps to the option starting with it
}
