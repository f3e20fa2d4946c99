import { useQueryClient } from "@tanstack/react-query";
import { useEffect } from "react";

import { tokensChanged } from "../api/tokens";
import { useSession } from "../session";
import { ApiTokens } from "./account/ApiTokens";
import { ChangePassword } from "./account/ChangePassword";

/** Every signed-in user's own account: password and API tokens. */
export function AccountPage() {
  const { user } = useSession();
  // A password change revokes every token: the list is asked for again after one.
  const client = useQueryClient();

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
      <ChangePassword onChanged={() => void tokensChanged(client)} />
      <ApiTokens />
    </section>
  );
}
