import { useEffect } from "react";

import { useSession } from "../session";
import { ApiTokens } from "./account/ApiTokens";
import { ChangePassword } from "./account/ChangePassword";

/** Every signed-in user's own account: password and API tokens. */
export function AccountPage() {
  const { user } = useSession();

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
      <ChangePassword />
      <ApiTokens />
    </section>
  );
}
