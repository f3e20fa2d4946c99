"""password checks keep their outcome: login_attempts.outcome ('failed', 'ok', 'forgiven'), so a
success forgives the account's failures without erasing the hashes counted against the
per-minute limit (store/login_throttle.py)

Revision ID: 0013
Revises: 0012
Create Date: 2026-12-04 10:00:00.000000
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = '0013'
down_revision = '0012'
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table('login_attempts', schema=None) as batch_op:
        # Existing rows were all failures: successes deleted the account's rows.
        batch_op.add_column(sa.Column('outcome', sa.String(length=8), nullable=False,
                                      server_default='failed'))


def downgrade() -> None:
    # The old code reads every row as a failure: drop the ones that were not.
    op.execute(sa.text("DELETE FROM login_attempts WHERE outcome <> 'failed'"))
    with op.batch_alter_table('login_attempts', schema=None) as batch_op:
        batch_op.drop_column('outcome')
