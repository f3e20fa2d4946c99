"""Domain services: what the routes ask for, between HTTP and the store.

Each module is one domain's use cases as keyword-only functions. What they need of the app
(the report service, the log signer, the database to open a second session on) is passed in
explicitly, from the one `AppServices` object the app factory builds (`app.py`); routes get
it through a FastAPI dependency (`web/deps.py`, `Services`) and only translate HTTP. The store
below holds tables and queries. Nothing here imports `web` or `cli`."""
