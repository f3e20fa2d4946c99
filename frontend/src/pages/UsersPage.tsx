import { type FormEvent, useEffect, useState } from "react";

import type { User } from "../api/client";
import { useCreateUser, useUpdateUser, useUsers } from "../api/users";
import { type Column, DataTable } from "../components/DataTable";
import { ErrorMessage, Loading, Notice } from "../components/Status";
import { ROLE_LABEL, ROLES, type Role } from "../roles";
import { useSession } from "../session";
import { ResetPassword } from "./users/ResetPassword";
import { RoleChangeDialog } from "./RoleChangeDialog";

export function UsersPage() {
  const me = useSession().user;
  const { data, error, isPending: loading } = useUsers();
  const update = useUpdateUser();
  const [actionError, setActionError] = useState<unknown>(null);
  const [notice, setNotice] = useState<string | null>(null);
  const [pending, setPending] = useState<{ user: User; role: Role } | null>(null);

  useEffect(() => {
    document.title = "Users · Countersign";
  }, []);

  const patch = (user: User, body: { disabled: boolean }, done: string) => {
    setActionError(null);
    setNotice(null);
    update.mutate({ user, patch: body }, { onSuccess: () => setNotice(done), onError: setActionError });
  };

  const columns: Column<User>[] = [
    { header: "Username", cell: (u) => <code>{u.username}</code> },
    { header: "Name", cell: (u) => u.display_name },
    {
      header: "Role",
      cell: (u) => (
        <>
          <label className="visually-hidden" htmlFor={`role-${u.id}`}>
            Role of {u.username}
          </label>
          <select
            id={`role-${u.id}`}
            value={u.role}
            disabled={u.id === me.id}
            onChange={(e) => setPending({ user: u, role: e.target.value as Role })}
          >
            {ROLES.map((r) => (
              <option key={r} value={r}>
                {ROLE_LABEL[r]}
              </option>
            ))}
          </select>
        </>
      ),
    },
    { header: "State", cell: (u) => (u.disabled ? "Disabled" : "Active") },
    {
      header: "Actions",
      cell: (u) => (
        <>
          {u.id === me.id ? (
            <span className="hint">you</span>
          ) : (
            <button
              type="button"
              onClick={() =>
                patch(u, { disabled: !u.disabled }, `${u.username} ${u.disabled ? "enabled" : "disabled"}.`)
              }
            >
              {u.disabled ? "Enable" : "Disable"}
              <span className="visually-hidden"> {u.username}</span>
            </button>
          )}
          {u.id !== me.id && (
            <ResetPassword
              user={u}
              onDone={(done) => {
                setNotice(done);
              }}
            />
          )}
        </>
      ),
    },
  ];

  return (
    <section aria-labelledby="users-title">
      <h1 id="users-title" tabIndex={-1}>
        Users
      </h1>
      <ErrorMessage error={error ?? actionError} />
      {notice && <Notice>{notice}</Notice>}
      {pending && (
        <RoleChangeDialog
          key={`${pending.user.id}:${pending.role}`}
          user={pending.user}
          role={pending.role}
          onCancel={() => setPending(null)}
          onDone={(message) => {
            setPending(null);
            setNotice(message);
          }}
        />
      )}
      {loading && !data ? (
        <Loading what="users" />
      ) : data ? (
        <DataTable
          caption="Accounts"
          className="users"
          columns={columns}
          rows={data}
          rowKey={(u) => u.id}
          rowClassName={(u) => (u.disabled ? "disabled" : undefined)}
        />
      ) : null}
      <CreateUser
        onCreated={(u) => setNotice(`Created ${u.role} ${u.username}.`)}
      />
    </section>
  );
}

function CreateUser({ onCreated }: { onCreated: (user: User) => void }) {
  const empty = {
    username: "",
    display_name: "",
    role: "operator" as Role,
    password: "",
    admin_password: "",
  };
  const [form, setForm] = useState(empty);
  const create = useCreateUser();
  const error = create.error;
  const busy = create.isPending;

  const submit = (event: FormEvent) => {
    event.preventDefault();
    // A new supervisor or admin needs the admin's own password; other roles send none.
    const granting = form.role === "supervisor" || form.role === "admin";
    const body = { ...form, admin_password: granting ? form.admin_password : null };
    create.mutate(body, {
      onSuccess: (user) => {
        setForm(empty);
        onCreated(user);
      },
    });
  };

  return (
    <form className="card" onSubmit={submit} aria-labelledby="create-user-title">
      <h2 id="create-user-title">Create a user</h2>
      <div className="grid">
        <label htmlFor="new-username">Username</label>
        <input
          id="new-username"
          required
          autoComplete="off"
          value={form.username}
          onChange={(e) => setForm({ ...form, username: e.target.value })}
        />
        <label htmlFor="new-display-name">Display name</label>
        <input
          id="new-display-name"
          autoComplete="off"
          value={form.display_name}
          onChange={(e) => setForm({ ...form, display_name: e.target.value })}
        />
        <label htmlFor="new-role">Role</label>
        <select
          id="new-role"
          value={form.role}
          onChange={(e) => setForm({ ...form, role: e.target.value as Role })}
        >
          {ROLES.map((r) => (
            <option key={r} value={r}>
              {ROLE_LABEL[r]}
            </option>
          ))}
        </select>
        <label htmlFor="new-password">Initial password</label>
        <input
          id="new-password"
          type="password"
          required
          autoComplete="new-password"
          value={form.password}
          onChange={(e) => setForm({ ...form, password: e.target.value })}
        />
        {(form.role === "supervisor" || form.role === "admin") && (
          <>
            <label htmlFor="new-admin-password">Your password (to create a {form.role})</label>
            <input
              id="new-admin-password"
              type="password"
              required
              autoComplete="current-password"
              value={form.admin_password}
              onChange={(e) => setForm({ ...form, admin_password: e.target.value })}
            />
          </>
        )}
      </div>
      <ErrorMessage error={error} />
      <button type="submit" className="primary" disabled={busy}>
        {busy ? "Creating…" : "Create user"}
      </button>
    </form>
  );
}
