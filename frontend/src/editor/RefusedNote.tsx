import { useEditor } from "./store";

/** "Not saved: ..." beside the field whose value the server refused (refusal.ts). */
export function RefusedNote({ fieldId }: { fieldId: string }) {
  const refusal = useEditor((s) => s.refusal);
  if (refusal?.fieldId !== fieldId) return null;
  return (
    <span className="field-refused" role="alert" id={`${fieldId}-refused`} data-testid={`refused-${fieldId}`}>
      Not saved: {refusal.message}
    </span>
  );
}
