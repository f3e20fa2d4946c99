"""decisions: one decision (and one revocation) per submission, one active submission per
version, as unique partial indexes

Revision ID: 0005
Revises: 0004
Create Date: 2026-12-01 23:30:00
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = '0005'
down_revision = '0004'
branch_labels = None
depends_on = None

DECIDED = "decision IN ('approved', 'rejected')"
REVOKED = "decision = 'revoked'"
ACTIVE = "state IN ('submitted', 'approved')"


def _refuse_duplicates() -> None:
    """A database that already holds two decisions on one submission (the race this closes)
    cannot take the index: say which rows, rather than fail with the engine's message. The
    rows are evidence (approvals are append-only), so they are not changed here."""
    bind = op.get_bind()
    found = []
    for table, column, where in (("approvals", "submission_id", DECIDED),
                                 ("approvals", "submission_id", REVOKED),
                                 ("submissions", "version_id", ACTIVE)):
        rows = bind.execute(sa.text(
            f"SELECT {column}, count(*) FROM {table} WHERE {where} GROUP BY {column} "
            "HAVING count(*) > 1")).all()
        found += [f"{table}.{column}={value} ({n} rows where {where})" for value, n in rows]
    if found:
        raise RuntimeError("cannot add the unique decision indexes: the database holds "
                           "duplicates (" + "; ".join(found) + "); resolve them first")


def upgrade() -> None:
    _refuse_duplicates()
    op.create_index('uq_approvals_decision_submission', 'approvals', ['submission_id'],
                    unique=True, sqlite_where=sa.text(DECIDED),
                    postgresql_where=sa.text(DECIDED))
    op.create_index('uq_approvals_revocation_submission', 'approvals', ['submission_id'],
                    unique=True, sqlite_where=sa.text(REVOKED),
                    postgresql_where=sa.text(REVOKED))
    op.create_index('uq_submissions_active_version', 'submissions', ['version_id'],
                    unique=True, sqlite_where=sa.text(ACTIVE), postgresql_where=sa.text(ACTIVE))

def downgrade() -> None:
    op.drop_index('uq_submissions_active_version', table_name='submissions')
    op.drop_index('uq_approvals_revocation_submission', table_name='approvals')
    op.drop_index('uq_approvals_decision_submission', table_name='approvals')
