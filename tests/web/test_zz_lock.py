# ruff: noqa
from __future__ import annotations
import sqlite3, threading, time, json
from .conftest import World
from .approval_helpers import MISSION, new_version, register_key, prepare, sign_prepared, submit
from ..heavy_orders import heavy_orders
from countersign.orders.examples import load_example, example_bytes

class Sampler:
    def __init__(self, path):
        self.path = path; self.stop = False; self.held_since = None; self.longest = 0.0
        self.t = threading.Thread(target=self.run, daemon=True); self.t.start()
    def run(self):
        c = sqlite3.connect(self.path, timeout=0, isolation_level=None, check_same_thread=False)
        while not self.stop:
            try:
                c.execute("BEGIN IMMEDIATE"); c.execute("ROLLBACK")
                if self.held_since is not None:
                    self.longest = max(self.longest, time.monotonic() - self.held_since)
                self.held_since = None
            except sqlite3.OperationalError:
                if self.held_since is None: self.held_since = time.monotonic()
            time.sleep(0.002)
    def measure(self, label, fn):
        self.longest = 0.0; self.held_since = None
        t = time.monotonic(); r = fn(); dt = time.monotonic() - t
        time.sleep(0.01)
        print(f"{label}: {r.status_code} took {dt*1000:.0f} ms, lock held at most {self.longest*1000:.0f} ms  {r.text[:100] if r.is_error else ''}")
        return r

def test_lock(world: World) -> None:
    if world.database.engine.dialect.name != "sqlite": return
    s = Sampler(world.database.engine.url.database)
    op = world.client("operator"); sup = world.client("supervisor")
    heavy = heavy_orders(40, 20); heavy["id"] = "heavy"
    s.measure("create heavy", lambda: op.post("/api/missions", json=heavy))
    heavy["title"] = "changed"
    s.measure("draft heavy", lambda: op.put("/api/missions/heavy/draft", json={"orders": heavy}, headers={"If-Match": '"1"'}))
    r = s.measure("version heavy", lambda: op.post("/api/missions/heavy/versions", json={}))
    s.measure("submit heavy", lambda: op.post("/api/missions/heavy/versions/1/submit"))
    s.measure("version ex", lambda: op.post(f"/api/missions/{MISSION}/versions", json={}))
    s.measure("submit ex", lambda: op.post(f"/api/missions/{MISSION}/versions/1/submit"))
    signer = register_key(sup)
    r = s.measure("prepare", lambda: sup.post("/api/submissions/1/statement", json={"decision": "approved", "reason": "", "key_id": signer.key_id}))
    from countersign.approvals import dsse
    from .conftest import PASSWORD
    if r.status_code == 200:
        s.measure("decide", lambda: sup.post("/api/submissions/1/decision", json={"envelope": sign_prepared(r.json(), signer), "password": PASSWORD}))
    s.measure("campaign", lambda: op.post("/api/missions/heavy/versions/1/campaigns", json={"simulations": 4}))
    s.measure("plan problem", lambda: op.post(f"/api/missions/{MISSION}/plan-problem", json={"start": [36.7, -121.9], "recovery": [36.7, -121.9]}))
    s.measure("layout", lambda: op.put(f"/api/missions/{MISSION}/layout", json={"layout": {}}))
    s.measure("import", lambda: op.post("/api/import", content=example_bytes("transect-survey"), headers={"content-type": "application/json"}))
    s.measure("delete", lambda: op.delete(f"/api/missions/{MISSION}"))
    s.stop = True
