"""validation reports keyed by the checker fingerprint: checker_version widened from the
package version ("0.1.0") to `sha256:` and 64 hex digits (verify.fingerprint)

Revision ID: 0011
Revises: 0010
Create Date: 2026-12-04 05:30:00.000000
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = '0011'
down_revision = '0010'
branch_labels = None
depends_on = None


def upgrade() -> None:
    # Reports stored under the package version cannot say which checks made them: none may be
    # shown again, and each is recomputed (and stored under its fingerprint) when next read.
    op.execute(sa.text("DELETE FROM validation_reports"))
    with op.batch_alter_table('validation_reports', schema=None) as batch_op:
        batch_op.alter_column('checker_version', existing_type=sa.String(length=32),
                              type_=sa.String(length=71), existing_nullable=False)


def downgrade() -> None:
    # The fingerprints do not fit the old column; reports are a cache and are recomputed.
    op.execute(sa.text("DELETE FROM validation_reports"))
    with op.batch_alter_table('validation_reports', schema=None) as batch_op:
        batch_op.alter_column('checker_version', existing_type=sa.String(length=71),
                              type_=sa.String(length=32), existing_nullable=False)
