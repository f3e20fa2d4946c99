"""each event's target, for the activity log's filter

Revision ID: 0009
Revises: 0008
Create Date: 2026-12-02 06:45:00
"""

from __future__ import annotations

import json

import sqlalchemy as sa
from alembic import op

from countersign.store.event_words import event_target

revision = '0009'
down_revision = '0008'
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table('events', schema=None) as batch_op:
        batch_op.add_column(sa.Column('target', sa.String(length=200), nullable=True))
        batch_op.create_index(batch_op.f('ix_events_target'), ['target'], unique=False)
    # Events already logged get the target their kind, mission and detail give (the same
    # function the app uses when it records one).
    bind = op.get_bind()
    events = sa.table('events', sa.column('id', sa.BigInteger), sa.column('kind', sa.String),
                      sa.column('mission_id', sa.String), sa.column('detail', sa.JSON),
                      sa.column('target', sa.String))
    rows = bind.execute(sa.select(events.c.id, events.c.kind, events.c.mission_id,
                                  events.c.detail)).all()
    if not rows:
        return
    # The events table is append-only (revision 0002's triggers); only this new, derived
    # column is written, with the trigger lifted for the statement and put back after.
    postgres = bind.dialect.name == "postgresql"
    if postgres:
        op.execute("ALTER TABLE events DISABLE TRIGGER events_append_only")
    else:
        op.execute("DROP TRIGGER IF EXISTS events_no_update")
    for event_id, kind, mission, detail in rows:
        if isinstance(detail, str):
            detail = json.loads(detail)
        target = event_target(kind, mission, detail if isinstance(detail, dict) else {})
        if target is not None:
            bind.execute(events.update().where(events.c.id == event_id).values(target=target))
    if postgres:
        op.execute("ALTER TABLE events ENABLE TRIGGER events_append_only")
    else:
        op.execute("CREATE TRIGGER events_no_update BEFORE UPDATE ON events BEGIN "
                   "SELECT RAISE(ABORT, 'events is append-only: UPDATE refused'); END")


def downgrade() -> None:
    with op.batch_alter_table('events', schema=None) as batch_op:
        batch_op.drop_index(batch_op.f('ix_events_target'))
        batch_op.drop_column('target')
