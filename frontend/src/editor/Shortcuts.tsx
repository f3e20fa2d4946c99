/** The editor's keyboard shortcuts, listed in a dialog (the "Shortcuts" button, or "?" on the
 * canvas), not only in an aria-label that sighted keyboard users never see. */
import { useEffect, useRef } from "react";

export const SHORTCUTS: [string, string][] = [
  ["Tab", "Move from node to node (goals and terminals, before anything else on the canvas)"],
  ["Enter", "Select the focused node (the inspector shows it)"],
  ["Arrow keys", "Move the selected node"],
  ["G", "Add a goal"],
  ["F", "Focus the selected goal: show it with its predecessors and successors"],
  ["Escape", "Show the whole graph again after F"],
  ["L", "Auto layout"],
  ["O / double-click", "Open the selected goal's refinement on its own canvas"],
  ["U", "Up: back from a refinement to the canvas it belongs to"],
  ["Delete / Backspace", "Delete the selection"],
  ["Ctrl+C / Ctrl+V", "Copy / paste goals"],
  ["Ctrl+D", "Duplicate the selected goals"],
  ["Ctrl+Z", "Undo"],
  ["Ctrl+Shift+Z / Ctrl+Y", "Redo"],
  ["?", "This list"],
];

export function ShortcutsDialog({ onClose }: { onClose: () => void }) {
  const close = useRef<HTMLButtonElement>(null);
  useEffect(() => {
    const opener = document.activeElement as HTMLElement | null;
    close.current?.focus();
    return () => opener?.focus();
  }, []);
  return (
    <div className="dialog-backdrop" onClick={(e) => e.target === e.currentTarget && onClose()}>
      <div
        className="dialog shortcuts-dialog"
        role="dialog"
        aria-modal="true"
        aria-labelledby="shortcuts-title"
        data-testid="shortcuts-dialog"
        onKeyDown={(e) => {
          if (e.key === "Escape") {
            e.stopPropagation();
            onClose();
          }
        }}
      >
        <h2 id="shortcuts-title">Keyboard shortcuts of the graph editor</h2>
        <p className="hint">They act while the focus is on the canvas (not in a field). Connections are edited in the inspector: each outcome's next goal.</p>
        <dl>
          {SHORTCUTS.map(([keys, what]) => (
            <div key={keys} className="shortcut-row">
              <dt>{keys}</dt>
              <dd>{what}</dd>
            </div>
          ))}
        </dl>
        <button ref={close} type="button" onClick={onClose}>
          Close
        </button>
      </div>
    </div>
  );
}
