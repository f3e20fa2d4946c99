import { type FormEvent, useId, useState } from "react";

import type { User } from "../../api/client";
import { useUpdateUser } from "../../api/users";
import { ErrorMessage } from "../../components/Status";

/** An admin's reset of another user's password, confirmed with the admin's own password: the
 * server applies the password policy and ends every session and API token of that user. */
export function ResetPassword({ user, onDone }: { user: User; onDone: (notice: string) => void }) {
  const [open, setOpen] = useState(false);
  const [password, setPassword] = useState("");
  const [adminPassword, setAdminPassword] = useState("");
  const [error, setError] = useState<unknown>(null);
  const update = useUpdateUser();
  const busy = update.isPending;
  const id = useId();

  if (!open) {
    return (
      <button type="button" onClick={() => setOpen(true)}>
        Reset password<span className="visually-hidden"> of {user.username}</span>
      </button>
    );
  }

  const submit = async (event: FormEvent) => {
    event.preventDefault();
    setError(null);
    try {
      await update.mutateAsync({ user, patch: { password, admin_password: adminPassword } });
      setPassword("");
      setAdminPassword("");
      setOpen(false);
      onDone(`Password of ${user.username} reset; their sessions and API tokens have ended.`);
    } catch (e) {
      setError(e);
    }
  };

  return (
    <form className="reset-password" onSubmit={submit} aria-label={`Reset password of ${user.username}`}>
      <label htmlFor={`${id}-password`}>New password for {user.username}</label>
      <input
        id={`${id}-password`}
        type="password"
        required
        autoComplete="new-password"
        value={password}
        onChange={(e) => setPassword(e.target.value)}
      />
      <label htmlFor={`${id}-admin-password`}>Your password</label>
      <input
        id={`${id}-admin-password`}
        type="password"
        required
        autoComplete="current-password"
        value={adminPassword}
        onChange={(e) => setAdminPassword(e.target.value)}
      />
      <button type="submit" disabled={busy}>
        {busy ? "Resetting…" : "Set password"}
      </button>
      <button type="button" onClick={() => setOpen(false)}>
        Cancel
      </button>
      <ErrorMessage error={error} />
    </form>
  );
}
