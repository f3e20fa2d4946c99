/** Previous/next buttons over cursor pagination (the API hands out `next_cursor`). */
export function Pager({
  page,
  hasPrevious,
  hasNext,
  onPrevious,
  onNext,
  label,
}: {
  page: number;
  hasPrevious: boolean;
  hasNext: boolean;
  onPrevious: () => void;
  onNext: () => void;
  label: string;
}) {
  if (!hasPrevious && !hasNext) return null;
  return (
    <nav className="pager" aria-label={label}>
      <button type="button" onClick={onPrevious} disabled={!hasPrevious}>
        ← Previous
      </button>
      <span aria-live="polite">Page {page}</span>
      <button type="button" onClick={onNext} disabled={!hasNext}>
        Next →
      </button>
    </nav>
  );
}

/** The cursors behind each page seen so far, so "Previous" needs no backwards cursor. */
export interface CursorStack {
  cursors: (string | null)[];
}

export function firstPage(): CursorStack {
  return { cursors: [null] };
}

export function nextPage(stack: CursorStack, cursor: string): CursorStack {
  return { cursors: [...stack.cursors, cursor] };
}

export function previousPage(stack: CursorStack): CursorStack {
  return stack.cursors.length > 1 ? { cursors: stack.cursors.slice(0, -1) } : stack;
}

export function currentCursor(stack: CursorStack): string | null {
  return stack.cursors[stack.cursors.length - 1] ?? null;
}
