"""A submission cites a stored rehearsal record of exactly its version; the approval
statement names the record's digest and the audit bundle carries the record.

The records are stored through the same store function the stop route uses (the rehearsal
itself is exercised in test_rehearsals.py)."""

from __future__ import annotations

from countersign.approvals.bundle import verify_bundle
from countersign.orders.reader import orders_from_data
from countersign.rehearse.manager import Rehearsal, RehearsalOptions
from countersign.store.rehearsals import get_record, save_record
from countersign.store.tables import MissionVersion, User
from countersign.web.routes.rehearsal_schemas import RehearsalRecordOut

from .approval_helpers import MISSION, approve, counts, new_version, register_key, submit
from .conftest import World
from .described import assert_described


def _stored_record(world: World, number: int) -> str:
    """A real record of this version (a headless simulated rehearsal: no viser, so its
    replay page is a stand-in), stored as the stop route stores one."""
    with world.database.session() as db:
        version = db.query(MissionVersion).filter_by(mission_id=MISSION, number=number).one()
        owner = db.query(User).filter_by(username=world.usernames["operator"]).one()
        rehearsal = Rehearsal(orders_from_data(version.orders), owner=str(owner.id),
                              options=RehearsalOptions(source="simulate", seed=number),
                              headless=True)
        rehearsal.run_headless(max_wall_s=30)
        record = rehearsal.stop()
        assert record.to_json()["orders"]["digest"] == version.digest
        save_record(db, digest=record.digest, record=record.to_json(),
                    replay_html=b"<!doctype html><p>headless: no scene", mission_id=MISSION,
                    version=number, orders_digest=version.digest, source="simulate",
                    owner=owner, rehearsal_id=rehearsal.id, signer=world.database.log_signer)
    return record.digest


def test_submission_with_record_is_cited_by_the_approval_and_the_bundle(world: World) -> None:
    number = new_version(world)
    digest = _stored_record(world, number)
    operator = world.client("operator")
    response = operator.post(f"/api/missions/{MISSION}/versions/{number}/submit",
                             json={"rehearsal": digest})
    assert response.status_code == 201, response.text
    assert response.json()["rehearsal"] == digest
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    approval = approve(world, supervisor, signer, response.json()["id"])
    detail = world.client("auditor").get(f"/api/approvals/{approval['id']}").json()
    assert detail["statement"]["predicate"]["rehearsal_digest"] == digest
    assert detail["rehearsal"]["digest"] == digest
    assert detail["rehearsal"]["record"]["outcomes"]
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    assert bundle["rehearsals"][digest]["orders"]["digest"] == approval["digest"]
    assert verify_bundle(bundle).ok
    # Both answers are the stored record, which RehearsalRecordOut describes field for field.
    with world.database.session() as db:
        stored = get_record(db, digest).record
    assert detail["rehearsal"]["record"] == stored and bundle["rehearsals"][digest] == stored
    assert_described(RehearsalRecordOut, stored)
    # Offline, the cited record must be there and hash to the cited digest.
    tampered = dict(bundle, rehearsals={digest: dict(bundle["rehearsals"][digest], seed=99)})
    assert any("does not hash" in p for p in verify_bundle(tampered).problems)
    assert any("lacks the rehearsal record" in p
               for p in verify_bundle(dict(bundle, rehearsals={})).problems)


def test_record_attached_after_submission_and_approval_without_one_cites_null(
        world: World) -> None:
    number = new_version(world)
    submission = submit(world, number)
    digest = _stored_record(world, number)
    operator = world.client("operator")
    response = operator.post(f"/api/submissions/{submission}/rehearsal",
                             json={"rehearsal": digest})
    assert response.status_code == 200, response.text
    assert operator.get(f"/api/submissions/{submission}").json()["rehearsal"] == digest
    kinds = [e["kind"] for e in world.client("admin").get("/api/events",
                                                           params={"limit": 1000}).json()]
    assert "submission.rehearsal_attached" in kinds

    other = new_version(world)
    plain = submit(world, other)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    approval = approve(world, supervisor, signer, plain)
    detail = world.client("auditor").get(f"/api/approvals/{approval['id']}").json()
    assert detail["statement"]["predicate"]["rehearsal_digest"] is None
    assert detail["rehearsal"] is None


def test_record_of_other_orders_or_unknown_or_foreign_is_refused(world: World) -> None:
    first = new_version(world)
    record_of_first = _stored_record(world, first)
    operator = world.client("operator")
    draft = operator.get(f"/api/missions/{MISSION}").json()
    orders = dict(draft["orders"], title="Search and sample, revised")
    edited = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": orders},
                          headers={"If-Match": f'"{draft["revision"]}"'})
    assert edited.status_code == 200, edited.text
    second = new_version(world)
    before = counts(world.database)
    refused = operator.post(f"/api/missions/{MISSION}/versions/{second}/submit",
                            json={"rehearsal": record_of_first})
    assert refused.status_code == 409, refused.text
    assert refused.headers["content-type"] == "application/problem+json"
    assert "rehearse that version" in refused.json()["detail"]
    assert counts(world.database) == before  # nothing submitted

    unknown = operator.post(f"/api/missions/{MISSION}/versions/{second}/submit",
                            json={"rehearsal": "sha256:" + "0" * 64})
    assert unknown.status_code == 404
    malformed = operator.post(f"/api/missions/{MISSION}/versions/{second}/submit",
                              json={"rehearsal": "md5:abc"})
    assert malformed.status_code == 422

    submission = submit(world, second)
    record_of_second = _stored_record(world, second)
    # Only the submitting operator attaches; a supervisor may not.
    foreign = world.client("supervisor").post(f"/api/submissions/{submission}/rehearsal",
                                              json={"rehearsal": record_of_second})
    assert foreign.status_code == 403
    wrong = operator.post(f"/api/submissions/{submission}/rehearsal",
                          json={"rehearsal": record_of_first})
    assert wrong.status_code == 409
