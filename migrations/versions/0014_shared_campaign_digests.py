"""campaign digests are shared, not unique: two users' campaigns of the same spec and orders
seal the same record under the same digest (the second one to finish failed on
uq_campaigns_digest after all its runs)

Revision ID: 0014
Revises: 0013
Create Date: 2026-12-04 10:50:00.000000
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = '0014'
down_revision = '0013'
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table('campaigns', schema=None) as batch_op:
        batch_op.drop_constraint(batch_op.f('uq_campaigns_digest'), type_='unique')
        batch_op.create_index(batch_op.f('ix_campaigns_digest'), ['digest'], unique=False)


def downgrade() -> None:
    # Campaigns that share a digest keep the oldest one's: the later ones' records are equal.
    op.execute(sa.text(
        "UPDATE campaigns SET digest = NULL, record = NULL, state = 'failed' WHERE digest IS NOT "
        "NULL AND id NOT IN (SELECT min(id) FROM campaigns WHERE digest IS NOT NULL "
        "GROUP BY digest)"))
    with op.batch_alter_table('campaigns', schema=None) as batch_op:
        batch_op.drop_index(batch_op.f('ix_campaigns_digest'))
        batch_op.create_unique_constraint(batch_op.f('uq_campaigns_digest'), ['digest'])
