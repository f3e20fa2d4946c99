/**
 * Undo/redo over immutable states. Edits that share a `group` (typing in one field) within
 * `windowMs` coalesce into one step, so undo does not walk back one keystroke at a time.
 */

export interface History<T> {
  past: T[];
  present: T;
  future: T[];
  group: string | null;
  at: number;
}

export const HISTORY_LIMIT = 200;

export function createHistory<T>(present: T): History<T> {
  return { past: [], present, future: [], group: null, at: 0 };
}

export function push<T>(h: History<T>, next: T, options: { group?: string; now?: number; windowMs?: number } = {}): History<T> {
  if (next === h.present) return h;
  const now = options.now ?? Date.now();
  const group = options.group ?? null;
  if (group !== null && group === h.group && now - h.at <= (options.windowMs ?? 1500)) {
    return { ...h, present: next, future: [], at: now };
  }
  const past = [...h.past, h.present];
  if (past.length > HISTORY_LIMIT) past.shift();
  return { past, present: next, future: [], group, at: now };
}

export function canUndo<T>(h: History<T>): boolean {
  return h.past.length > 0;
}
export function canRedo<T>(h: History<T>): boolean {
  return h.future.length > 0;
}

export function undo<T>(h: History<T>): History<T> {
  const previous = h.past[h.past.length - 1];
  if (previous === undefined) return h;
  return { past: h.past.slice(0, -1), present: previous, future: [h.present, ...h.future], group: null, at: 0 };
}

export function redo<T>(h: History<T>): History<T> {
  const [next, ...rest] = h.future;
  if (next === undefined) return h;
  return { past: [...h.past, h.present], present: next, future: rest, group: null, at: 0 };
}

/** Replaces the present without an undo step (e.g. the server's copy after a reload). */
export function reset<T>(present: T): History<T> {
  return createHistory(present);
}
