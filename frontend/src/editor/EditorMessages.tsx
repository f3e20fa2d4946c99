/** What the editor says above the canvas: the save error, a notice (an import, a merge), the
 * live region's announcements and the highlighted path. */
import { ErrorMessage } from "../components/Status";
import { OUTCOME_LETTER, type Outcome } from "./graph";
import { useEditor } from "./store";

export function EditorMessages() {
  const saveError = useEditor((s) => s.saveError);
  const notice = useEditor((s) => s.notice);
  const connectMessage = useEditor((s) => s.connectMessage);
  return (
    <>
      <ErrorMessage error={saveError} />
      {notice && (
        <p className="message" data-testid="editor-notice">
          {notice}
        </p>
      )}
      <p className="visually-hidden" aria-live="polite">
        {connectMessage}
      </p>
      <HighlightNote />
    </>
  );
}

function HighlightNote() {
  const highlight = useEditor((s) => s.highlight);
  const showHighlight = useEditor((s) => s.showHighlight);
  if (!highlight) return null;
  const { path, label } = highlight;
  return (
    <p className="message" data-testid="highlight-note">
      Highlighted on the graph (thick edges marked ●): {label || "path"}{" "}
      <code>
        {path.goals.map((g, i) => `${g} ${OUTCOME_LETTER[path.outcomes[i] as Outcome] ?? "?"}`).join(" → ")}
        {path.terminal ? ` → ${path.terminal}` : ""}
      </code>{" "}
      <button type="button" onClick={() => showHighlight(null)}>
        Clear highlight
      </button>
    </p>
  );
}
