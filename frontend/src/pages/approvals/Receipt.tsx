/** The log signer's receipt for the decision just signed: shown to the supervisor as text. */
export function ReceiptNote({ receipt }: { receipt: string | null | undefined }) {
  if (!receipt) return <p data-testid="decision-receipt">The log signer returned no receipt for this entry.</p>;
  let fields: { index?: unknown; leaf?: unknown; time?: unknown } = {};
  try {
    fields = JSON.parse(receipt) as typeof fields;
  } catch {
    fields = {};
  }
  return (
    <details data-testid="decision-receipt">
      <summary>
        Log signer's receipt: entry {String(fields.index)}, leaf hash {String(fields.leaf).slice(0, 16)}…, at {String(fields.time)}
      </summary>
      <pre className="orders-text">{receipt}</pre>
    </details>
  );
}
