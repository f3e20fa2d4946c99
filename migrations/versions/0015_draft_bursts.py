"""editing bursts: a mission's open burst of draft saves, logged as one event when it ends
(store/draft_bursts.py)

Revision ID: 0015
Revises: 0014
Create Date: 2026-12-04 10:40:00.000000
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = '0015'
down_revision = '0014'
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table('missions', schema=None) as batch_op:
        batch_op.add_column(sa.Column('burst', sa.JSON(), nullable=True))
        batch_op.add_column(sa.Column('burst_at', sa.DateTime(timezone=True), nullable=True))
        batch_op.create_index(batch_op.f('ix_missions_burst_at'), ['burst_at'], unique=False)


def downgrade() -> None:
    # Open bursts are edits already saved in the draft; only their log entry is lost.
    with op.batch_alter_table('missions', schema=None) as batch_op:
        batch_op.drop_index(batch_op.f('ix_missions_burst_at'))
        batch_op.drop_column('burst_at')
        batch_op.drop_column('burst')
