"""vehicle registry versions: every saved profile kept, numbered per vehicle; the
profiles already in the registry become their vehicle's version 1

Revision ID: 0007
Revises: 0006
Create Date: 2026-12-02 01:40:00
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = '0007'
down_revision = '0006'
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        'vehicle_versions',
        sa.Column('vehicle_id', sa.String(length=100), nullable=False),
        sa.Column('number', sa.Integer(), nullable=False),
        sa.Column('title', sa.String(length=200), nullable=False),
        sa.Column('profile', sa.JSON(), nullable=False),
        sa.Column('saved_by', sa.String(length=64), nullable=True),
        sa.Column('saved_at', sa.DateTime(timezone=True), nullable=False),
        sa.PrimaryKeyConstraint('vehicle_id', 'number', name=op.f('pk_vehicle_versions')),
    )
    op.execute("INSERT INTO vehicle_versions (vehicle_id, number, title, profile, saved_by, "
               "saved_at) SELECT id, 1, title, profile, NULL, updated_at FROM vehicles")


def downgrade() -> None:
    op.drop_table('vehicle_versions')
