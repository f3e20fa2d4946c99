import { type FormEvent, useState } from "react";

import { useChangePassword } from "../../api/auth";
import { ErrorMessage, Notice } from "../../components/Status";

/** Change one's own password: the server checks the current one and the policy (its refusal
 * text is shown as is), then ends every other session and revokes every API token. */
export function ChangePassword() {
  const empty = { current: "", next: "", again: "" };
  const [form, setForm] = useState(empty);
  const [error, setError] = useState<unknown>(null);
  const [notice, setNotice] = useState<string | null>(null);
  const changePassword = useChangePassword();
  const busy = changePassword.isPending;

  const submit = async (event: FormEvent) => {
    event.preventDefault();
    setError(null);
    setNotice(null);
    if (form.next !== form.again) {
      setError("The two new passwords differ.");
      return;
    }
    try {
      await changePassword.mutateAsync({ current_password: form.current, new_password: form.next });
      setForm(empty);
      setNotice(
        "Password changed. Your other sessions have ended and your API tokens are revoked.",
      );
    } catch (e) {
      setError(e);
    }
  };

  const field = (name: keyof typeof empty, id: string, label: string, complete: string) => (
    <>
      <label htmlFor={id}>{label}</label>
      <input
        id={id}
        type="password"
        required
        autoComplete={complete}
        value={form[name]}
        onChange={(e) => setForm({ ...form, [name]: e.target.value })}
      />
    </>
  );

  return (
    <form className="card" onSubmit={submit} aria-labelledby="change-password-title">
      <h2 id="change-password-title">Change your password</h2>
      <p className="hint">
        At least 10 characters and hard to guess (common passwords, keyboard runs and your name
        are refused). Every other session of yours ends and every API token is revoked.
      </p>
      <div className="grid">
        {field("current", "current-password", "Current password", "current-password")}
        {field("next", "new-password", "New password", "new-password")}
        {field("again", "new-password-again", "New password again", "new-password")}
      </div>
      <ErrorMessage error={error} />
      {notice && <Notice>{notice}</Notice>}
      <button type="submit" className="primary" disabled={busy}>
        {busy ? "Changing…" : "Change password"}
      </button>
    </form>
  );
}
