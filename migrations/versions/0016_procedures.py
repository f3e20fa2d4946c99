"""procedures: the library of refinements saved by name and version, and their signed
approvals (store/procedure_tables.py)

Revision ID: 0016_procedures
Revises: 0015
Create Date: 2026-12-04 17:00:00.000000
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = '0016_procedures'
down_revision = '0015'
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        'procedures',
        sa.Column('name', sa.String(length=100), nullable=False),
        sa.Column('version', sa.Integer(), nullable=False),
        sa.Column('document', sa.JSON(), nullable=False),
        sa.Column('digest', sa.String(length=71), nullable=False),
        sa.Column('author_id', sa.Integer(), nullable=False),
        sa.Column('event_id', sa.BigInteger().with_variant(sa.Integer(), 'sqlite'),
                  nullable=False),
        sa.Column('updated_at', sa.DateTime(timezone=True), nullable=False),
        sa.ForeignKeyConstraint(['author_id'], ['users.id'],
                                name=op.f('fk_procedures_author_id_users')),
        sa.ForeignKeyConstraint(['event_id'], ['events.id'],
                                name=op.f('fk_procedures_event_id_events')),
        sa.PrimaryKeyConstraint('name', 'version', name=op.f('pk_procedures')),
        sa.UniqueConstraint('event_id', name=op.f('uq_procedures_event_id')),
    )
    with op.batch_alter_table('procedures', schema=None) as batch_op:
        batch_op.create_index(batch_op.f('ix_procedures_author_id'), ['author_id'], unique=False)
    op.create_table(
        'procedure_approvals',
        sa.Column('id', sa.Integer(), nullable=False),
        sa.Column('name', sa.String(length=100), nullable=False),
        sa.Column('version', sa.Integer(), nullable=False),
        sa.Column('procedure_digest', sa.String(length=71), nullable=False),
        sa.Column('decision', sa.String(length=16), nullable=False),
        sa.Column('reason', sa.Text(), nullable=False),
        sa.Column('supervisor_id', sa.Integer(), nullable=False),
        sa.Column('key_id', sa.String(length=64), nullable=False),
        sa.Column('envelope', sa.Text(), nullable=False),
        sa.Column('payload_digest', sa.String(length=71), nullable=False),
        sa.Column('event_id', sa.BigInteger().with_variant(sa.Integer(), 'sqlite'),
                  nullable=False),
        sa.Column('created_at', sa.DateTime(timezone=True), nullable=False),
        sa.ForeignKeyConstraint(['event_id'], ['events.id'],
                                name=op.f('fk_procedure_approvals_event_id_events')),
        sa.ForeignKeyConstraint(['key_id'], ['signing_keys.id'],
                                name=op.f('fk_procedure_approvals_key_id_signing_keys')),
        sa.ForeignKeyConstraint(['supervisor_id'], ['users.id'],
                                name=op.f('fk_procedure_approvals_supervisor_id_users')),
        sa.PrimaryKeyConstraint('id', name=op.f('pk_procedure_approvals')),
        sa.UniqueConstraint('event_id', name=op.f('uq_procedure_approvals_event_id')),
        sa.UniqueConstraint('payload_digest', name=op.f('uq_procedure_approvals_payload_digest')),
        sa.UniqueConstraint('name', 'version', name='uq_procedure_approvals_name_version'),
    )
    with op.batch_alter_table('procedure_approvals', schema=None) as batch_op:
        batch_op.create_index(batch_op.f('ix_procedure_approvals_name'), ['name'], unique=False)
        batch_op.create_index(batch_op.f('ix_procedure_approvals_supervisor_id'),
                              ['supervisor_id'], unique=False)


def downgrade() -> None:
    op.drop_table('procedure_approvals')
    op.drop_table('procedures')
