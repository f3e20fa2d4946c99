"""validation reports carry the mission list's summary (ok, errors, warnings) in columns, and
missions get (status, id) and (vehicle, id) indexes for the list's filters

Revision ID: 0012
Revises: 0011
Create Date: 2026-12-04 10:10:00.000000
"""

from __future__ import annotations

import json
from typing import Any

import sqlalchemy as sa
from alembic import op

revision = '0012'
down_revision = '0011'
branch_labels = None
depends_on = None

_BATCH = 200


def _summary(report: Any) -> dict[str, Any]:
    if isinstance(report, str | bytes):
        report = json.loads(report)
    findings = report.get("findings") or []
    errors = sum(finding.get("severity") == "error" for finding in findings)
    return {"ok": bool(report.get("ok")), "errors": errors, "warnings": len(findings) - errors}


def upgrade() -> None:
    with op.batch_alter_table('validation_reports', schema=None) as batch_op:
        batch_op.add_column(sa.Column('ok', sa.Boolean(), nullable=True))
        batch_op.add_column(sa.Column('errors', sa.Integer(), nullable=True))
        batch_op.add_column(sa.Column('warnings', sa.Integer(), nullable=True))
    with op.batch_alter_table('missions', schema=None) as batch_op:
        batch_op.create_index('ix_missions_status_id', ['status', 'id'], unique=False)
        batch_op.create_index('ix_missions_vehicle_id', ['vehicle', 'id'], unique=False)
    # Backfill: each stored report is decoded once here, so that no list has to again. Keys
    # are read first and reports in batches, to bound memory on a large cache.
    bind = op.get_bind()
    table = sa.table('validation_reports', sa.column('digest', sa.String),
                     sa.column('checker_version', sa.String), sa.column('report', sa.JSON),
                     sa.column('ok', sa.Boolean), sa.column('errors', sa.Integer),
                     sa.column('warnings', sa.Integer))
    keys = bind.execute(sa.select(table.c.digest, table.c.checker_version)).all()
    for start in range(0, len(keys), _BATCH):
        for digest, checker in keys[start:start + _BATCH]:
            report = bind.execute(sa.select(table.c.report).where(
                table.c.digest == digest, table.c.checker_version == checker)).scalar_one()
            bind.execute(table.update().where(
                table.c.digest == digest, table.c.checker_version == checker
            ).values(**_summary(report)))


def downgrade() -> None:
    with op.batch_alter_table('missions', schema=None) as batch_op:
        batch_op.drop_index('ix_missions_vehicle_id')
        batch_op.drop_index('ix_missions_status_id')
    with op.batch_alter_table('validation_reports', schema=None) as batch_op:
        batch_op.drop_column('warnings')
        batch_op.drop_column('errors')
        batch_op.drop_column('ok')
