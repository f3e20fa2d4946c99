import { type FormEvent, useEffect, useState } from "react";

import { api, ApiError, unwrap, type User } from "../api/client";
import { ErrorMessage, Loading, Notice } from "../components/Status";
import { ROLE_LABEL, ROLES, type Role } from "../roles";
import { useSession } from "../session";
import { useLoad } from "../useLoad";
import { ResetPassword } from "./users/ResetPassword";
import { RoleChangeDialog } from "./RoleChangeDialog";

export function UsersPage() {
  const me = useSession().user;
  const { data, error, loading, reload } = useLoad(async () => unwrap(await api.GET("/api/users")), []);
  const [actionError, setActionError] = useState<unknown>(null);
  const [notice, setNotice] = useState<string | null>(null);
  const [pending, setPending] = useState<{ user: User; role: Role } | null>(null);

  useEffect(() => {
    document.title = "Users · Countersign";
  }, []);

  const patch = async (user: User, body: { role?: string; disabled?: boolean }, done: string) => {
    setActionError(null);
    setNotice(null);
    const result = await api.PATCH("/api/users/{user_id}", {
      params: { path: { user_id: user.id } },
      body,
    });
    if (result.response.ok) {
      setNotice(done);
      reload();
    } else {
      setActionError(new ApiError(result.response.status, result.error));
    }
  };

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
            reload();
          }}
        />
      )}
      {loading && !data ? (
        <Loading what="users" />
      ) : data ? (
        <table className="users">
          <caption className="visually-hidden">Accounts</caption>
          <thead>
            <tr>
              <th scope="col">Username</th>
              <th scope="col">Name</th>
              <th scope="col">Role</th>
              <th scope="col">State</th>
              <th scope="col">Actions</th>
            </tr>
          </thead>
          <tbody>
            {data.map((u) => (
              <tr key={u.id} className={u.disabled ? "disabled" : undefined}>
                <td>
                  <code>{u.username}</code>
                </td>
                <td>{u.display_name}</td>
                <td>
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
                </td>
                <td>{u.disabled ? "Disabled" : "Active"}</td>
                <td>
                  {u.id === me.id ? (
                    <span className="hint">you</span>
                  ) : (
                    <button
                      type="button"
                      onClick={() =>
                        void patch(
                          u,
                          { disabled: !u.disabled },
                          `${u.username} ${u.disabled ? "enabled" : "disabled"}.`,
                        )
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
                        reload();
                      }}
                    />
                  )}
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      ) : null}
      <CreateUser
        onCreated={(u) => {
          setNotice(`Created ${u.role} ${u.username}.`);
          reload();
        }}
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
  const [error, setError] = useState<unknown>(null);
  const [busy, setBusy] = useState(false);

  const submit = async (event: FormEvent) => {
    event.preventDefault();
    setBusy(true);
    setError(null);
    try {
      // A new supervisor or admin needs the admin's own password; other roles send none.
      const granting = form.role === "supervisor" || form.role === "admin";
      const body = { ...form, admin_password: granting ? form.admin_password : null };
      const user = unwrap(await api.POST("/api/users", { body }));
      setForm(empty);
      onCreated(user);
    } catch (e) {
      setError(e);
    } finally {
      setBusy(false);
    }
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
