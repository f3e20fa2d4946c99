"""account hygiene: API token expiry and scopes, session idle timeout, login
attempts counted per client address as well as per account

Revision ID: 0006
Revises: 0005
Create Date: 2026-12-01 23:35:00
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = '0006'
down_revision = '0005'
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table('api_tokens') as batch:
        batch.add_column(sa.Column('expires_at', sa.DateTime(timezone=True), nullable=True))
        # Existing tokens keep what they could do: every scope.
        batch.add_column(sa.Column('scopes', sa.String(length=64), nullable=False,
                                   server_default='read write decide'))
    with op.batch_alter_table('sessions') as batch:
        batch.add_column(sa.Column('last_seen_at', sa.DateTime(timezone=True), nullable=True))
    with op.batch_alter_table('login_attempts') as batch:
        batch.add_column(sa.Column('address', sa.String(length=64), nullable=True))
        batch.create_index('ix_login_attempts_address', ['address'])


def downgrade() -> None:
    with op.batch_alter_table('login_attempts') as batch:
        batch.drop_index('ix_login_attempts_address')
        batch.drop_column('address')
    with op.batch_alter_table('sessions') as batch:
        batch.drop_column('last_seen_at')
    with op.batch_alter_table('api_tokens') as batch:
        batch.drop_column('scopes')
        batch.drop_column('expires_at')
