import { useEffect, useState } from "react";

import { useSession } from "../session";
import { ApiTokens } from "./account/ApiTokens";
import { ChangePassword } from "./account/ChangePassword";

/** Every signed-in user's own account: password and API tokens (issue 15). */
export function AccountPage() {
  const { user } = useSession();
  // A password change revokes every token: the list is loaded again after one.
  const [changes, setChanges] = useState(0);

  useEffect(() => {
    document.title = "Account · Countersign";
  }, []);

  return (
    <section aria-labelledby="account-title">
      <h1 id="account-title" tabIndex={-1}>
        Your account
      </h1>
      <p>
        Signed in as <code>{user.username}</code>
        {user.display_name ? ` (${user.display_name})` : ""}.
      </p>
      <ChangePassword onChanged={() => setChanges((n) => n + 1)} />
      <ApiTokens version={changes} />
    </section>
  );
}
