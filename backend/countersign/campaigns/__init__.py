"""Rehearsal campaigns: many seeded headless simulations of one version over
a sweep of faults, injection goals and seeds, and the statistics of their endings.

Pure: `spec` says which simulation each index is, `simulate` runs one, `stats` summarises the
results. Running them as jobs (procrastinate on PostgreSQL, in-process on SQLite) is
`countersign.jobs`; storing them is `countersign.store.campaigns`.
"""
