import { type ProfileChange, showValue } from "./profileDiff";

/** A profile diff as a list a reviewer reads: "behaviors: a, b → a, b, c". */
export function ProfileChanges({ changes, testId }: { changes: ProfileChange[]; testId?: string }) {
  if (changes.length === 0) return <p data-testid={testId}>No differences.</p>;
  return (
    <ul className="profile-diff" data-testid={testId}>
      {changes.map((c) => (
        <li key={c.field}>
          <code>{c.field}</code>: {showValue(c.before)} → {showValue(c.after)}
        </li>
      ))}
    </ul>
  );
}
