"""Whatever can make someone able to decide or to grant (a role change, an admin's reset of a
password, a new supervisor or admin, an API token with the `decide` scope) needs the acting
user's password, entered again: a script in their browser, or a stolen `write` token, holds
their session but not their password, and must not borrow a supervisor through a reset or a new
account. The check and its throttle are the decisions' (store/reauth.py)."""

from __future__ import annotations

from sqlalchemy.orm import Session

from .reauth import PasswordRequired, confirm_password
from .tables import User

# Roles that can sign decisions or grant roles: creating such a user hands out that power.
GRANTING_ROLES = frozenset({"supervisor", "admin"})


def confirm_grant(db: Session, actor: User, password: str | None, *, action: str,
                  undone: str, field: str = "admin_password") -> None:
    """Call first in the request's transaction (a wrong password commits its attempt, nothing
    else). `action` names what needs the password, `undone` what did not happen."""
    if not password:
        raise PasswordRequired(f"{action} needs your password, entered again ({field})")
    confirm_password(db, username=actor.username, password_hash=actor.password_hash,
                     password=password, wrong=f"the password is wrong; {undone}")


def confirm_role_change(db: Session, admin: User, password: str | None) -> None:
    confirm_grant(db, admin, password, action="a role change", undone="no role was changed")
