/**
 * Confirms a role change with the admin's password, entered again (the server checks it): a
 * drop-down moved by arrow keys, or a script in this browser, changes no one's role.
 */
import { type FormEvent, useEffect, useRef, useState } from "react";

import type { User } from "../api/client";
import { useUpdateUser } from "../api/users";
import { ErrorMessage } from "../components/Status";
import { ROLE_LABEL, type Role } from "../roles";

export function RoleChangeDialog({
  user,
  role,
  onDone,
  onCancel,
}: {
  user: User;
  role: Role;
  onDone: (message: string) => void;
  onCancel: () => void;
}) {
  const [password, setPassword] = useState("");
  const [error, setError] = useState<unknown>(null);
  const update = useUpdateUser();
  const busy = update.isPending;
  const field = useRef<HTMLInputElement>(null);
  useEffect(() => field.current?.focus(), []);

  const confirm = async (event: FormEvent) => {
    event.preventDefault();
    if (!password) {
      setError("Enter your password to change a role.");
      return;
    }
    setError(null);
    try {
      await update.mutateAsync({ user, patch: { role, admin_password: password } });
      onDone(`${user.username} is now ${role}.`);
    } catch (e) {
      setError(e);
    }
  };

  const from = ROLE_LABEL[user.role as Role] ?? user.role;
  return (
    <div
      className="dialog-backdrop"
      onKeyDown={(e) => {
        if (e.key === "Escape") onCancel();
      }}
    >
      <form role="dialog" aria-modal="true" aria-labelledby="role-change-title" className="card dialog" onSubmit={(e) => void confirm(e)}>
        <h2 id="role-change-title">Change the role of {user.username}</h2>
        <p data-testid="role-change-summary">
          From {from} to {ROLE_LABEL[role]}. Confirm with your own password.
        </p>
        <label htmlFor="role-change-password">Your password</label>
        <input
          id="role-change-password"
          ref={field}
          type="password"
          autoComplete="current-password"
          value={password}
          onChange={(e) => setPassword(e.target.value)}
        />
        <ErrorMessage error={error} />
        <p className="actions">
          <button type="submit" className="primary" disabled={busy}>
            Change role
          </button>
          <button type="button" onClick={onCancel}>
            Cancel
          </button>
        </p>
      </form>
    </div>
  );
}
