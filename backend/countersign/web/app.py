"""The FastAPI application factory: database migrated to head, routes, problems, the SPA."""

from __future__ import annotations

import gc
from collections.abc import AsyncIterator, Callable
from contextlib import AbstractAsyncContextManager, asynccontextmanager
from pathlib import Path

import anyio.to_thread
from fastapi import FastAPI
from fastapi.responses import FileResponse, JSONResponse, Response
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from .. import __version__
from ..map_tiles import tile_origin
from ..services.app import AppServices
from ..services.log_signer import open_log_signer
from ..settings import Settings
from ..store.db import REQUEST_THREADS, Database
from ..store.hashing import HASHER
from ..verify import fingerprint
from . import api_docs, openapi_links, problems
from .access_log import hide_tickets
from .client_address import ClientAddress
from .fair import PlanSlots, RateLimiter
from .host_pool import HostPoolAddress, HostPoolClient
from .rehearsal_hub import RehearsalHub
from .routes import (
    admin,
    approvals,
    auth,
    charts,
    client_config,
    document,
    log_witness,
    missions,
    planning,
    procedures,
    rehearsals,
    standing,
    vehicles,
)
from .routes import campaigns as campaign_routes
from .routes import executions as execution_routes
from .routes import exports as export_routes
from .validation_pool import WARM_WAIT_S, ValidationPool
from .validations import ValidationPools


class BodyLimit:
    """Refuse request bodies above a size before reading them into memory (413)."""

    def __init__(self, app: ASGIApp, limit: int) -> None:
        self.app, self.limit = app, limit

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        length = dict(scope.get("headers", [])).get(b"content-length")
        if length is not None and length.isdigit() and int(length) > self.limit:
            await self._too_large(scope, receive, send)
            return
        seen = 0

        async def limited() -> Message:
            nonlocal seen
            message = await receive()
            seen += len(message.get("body", b""))
            if seen > self.limit:
                raise _TooLarge
            return message

        try:
            await self.app(scope, limited, send)
        except _TooLarge:
            await self._too_large(scope, receive, send)

    async def _too_large(self, scope: Scope, receive: Receive, send: Send) -> None:
        response = problems.problem(413, f"the request body is larger than {self.limit} bytes")
        await response(scope, receive, send)


class _TooLarge(Exception):
    pass


# Scripts: the app's own files only (no inline script, no eval), and every DOM sink that could
# run script (innerHTML, script.src...) refuses strings: Trusted Types with one policy only,
# `layout-worker`, which passes nothing but the app's own layout worker script (same origin,
# frontend/src/editor/layoutClient.ts) to `new Worker`.
# Frames: the rehearsal viewer only, which runs sandboxed in an opaque origin (viser_proxy.py).
# The second policy, `map-worker`, passes only MapLibre's own worker module (same origin,
# frontend/src/map/trusted.ts) and creates no HTML, so the map cannot turn a string into markup.
# Images: the app's own and data: URLs, plus the configured map tiles' origin (map_tiles.py);
# MapLibre fetches tiles with fetch(), so that origin is also the one extra connect-src.
APP_CSP = ("default-src 'self'; script-src 'self'; object-src 'none'; base-uri 'none'; "
           "form-action 'self'; img-src 'self' data:; style-src 'self' 'unsafe-inline'; "
           "frame-src 'self'; frame-ancestors 'none'; "
           "require-trusted-types-for 'script'; trusted-types layout-worker map-worker")


def app_csp(map_tiles: str | None) -> str:
    if map_tiles is None:
        return APP_CSP
    origin = tile_origin(map_tiles)
    return APP_CSP.replace("img-src 'self' data:;",
                           f"img-src 'self' data: {origin}; connect-src 'self' {origin};")
SECURITY_HEADERS = {
    "X-Content-Type-Options": "nosniff",
    "X-Frame-Options": "DENY",
    "Referrer-Policy": "no-referrer",
    "Content-Security-Policy": APP_CSP,
}
HSTS = (b"strict-transport-security", b"max-age=31536000; includeSubDomains")


class SecurityHeaders:
    """Add SECURITY_HEADERS (and no-store on /api/) to every response that lacks them. Plain
    ASGI: Starlette's @app.middleware("http") costs a task and a stream per request."""

    def __init__(self, app: ASGIApp, *, secure_cookies: bool = False,
                 csp: str = APP_CSP) -> None:
        self.app, self.secure_cookies = app, secure_cookies
        self.api = [(name.lower().encode(), value.encode())
                    for name, value in {**SECURITY_HEADERS,
                                        "Content-Security-Policy": csp}.items()]

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        extra = list(self.api)
        # HSTS only where the browser reached us over TLS (or behind a TLS proxy, which
        # COUNTERSIGN_SECURE_COOKIES declares): over plain HTTP it is ignored or wrong.
        if scope.get("scheme") == "https" or self.secure_cookies:
            extra.append(HSTS)
        if scope["path"].startswith("/api/"):
            extra.append((b"cache-control", b"no-store"))

        async def with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = list(message.get("headers", []))
                present = {name.lower() for name, _ in headers}
                headers.extend(h for h in extra if h[0] not in present)
                message = {**message, "headers": headers}
            await send(message)

        await self.app(scope, receive, with_headers)


# Allocations between young garbage collections in a serving process (Python's default: 700).
YOUNG_GC_THRESHOLD = 20_000


def _validation_pool(settings: Settings, host_pool: HostPoolAddress | None
                     ) -> ValidationPools | None:
    """The host's pool (through a client) or one of this process's own, or None (validate in
    the request threads). Each is typed as the protocol on its own, so that mypy names the
    method one lacks."""
    if host_pool is not None:
        client: ValidationPools = HostPoolClient(host_pool, settings.validation_processes)
        return client
    if settings.validation_processes > 0:
        local: ValidationPools = ValidationPool(settings.validation_processes)
        return local
    return None


def create_app(settings: Settings, database: Database | None = None,
               host_pool: HostPoolAddress | None = None) -> FastAPI:
    """The app; with `host_pool` (serve --workers N) it validates in the pool every server
    process of the host shares (host_pool.py), else in a pool of its own."""
    settings.prepare()
    hide_tickets()  # before the server logs its first request
    services = _services(settings, database or Database(settings.database_url))
    hub = RehearsalHub()
    # One schema per model: recursive orders (a goal's refinement holds goals)
    # would otherwise split into Orders-Input and Orders-Output, which the routes' own
    # `#/components/schemas/Orders` references do not name.
    app = FastAPI(title="Countersign", version=__version__, docs_url=None,
                  openapi_url="/api/openapi.json", redoc_url=None,
                  lifespan=_lifespan(settings, services, hub, host_pool),
                  separate_input_output_schemas=False)
    app.state.settings = settings
    app.state.database = services.database
    app.state.services = services  # routes: web/deps.py, Services
    app.state.rehearsals = hub
    app.state.rehearsal_proxies = []
    app.state.rate_limiter = RateLimiter()
    app.state.plan_slots = PlanSlots()
    problems.install(app)

    app.add_middleware(SecurityHeaders, secure_cookies=settings.secure_cookies,
                       csp=app_csp(settings.map_tiles))
    api_docs.install(app)
    openapi_links.install(app)
    _include_routes(app)
    _serve_frontend(app, settings.frontend_dist)
    app.add_middleware(BodyLimit, limit=settings.max_body_bytes)
    app.add_middleware(ClientAddress)  # every route's password check counts its address
    return app


def _services(settings: Settings, database: Database) -> AppServices:
    """The migrated database and the services built on it (its log signer opened here)."""
    database.migrate()
    signer = database.log_signer
    if signer is None:
        # Refuses to start on an unusable key file (readable by others, say).
        signer = database.log_signer = open_log_signer(settings, database)
    return AppServices.of(database, signer)


def _lifespan(settings: Settings, services: AppServices, hub: RehearsalHub,
              host_pool: HostPoolAddress | None
              ) -> Callable[[FastAPI], AbstractAsyncContextManager[None]]:
    """What a running server starts before its first request and stops after its last: the
    validation pool, the campaign runner (SQLite), the password hashing process."""

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        # As many threads as the database pool keeps connections for (store/db.py).
        anyio.to_thread.current_default_thread_limiter().total_tokens = REQUEST_THREADS
        # What exists once the app is built (modules, the ontology, compiled queries) lives as
        # long as the process: leave it out of every later full collection, which otherwise
        # walks it all and stops the process for tens of milliseconds each time.
        gc.collect()
        gc.freeze()
        # A request allocates in tens of thousands (a 1,000-goal draft parsed, checked and
        # stored; its report unpickled): with the default first threshold of 700 a one-goal
        # edit ran some 76 collections, whose older generations walk the report caches, 40 ms
        # of its CPU. Fewer, larger young collections: 2 per edit, 13 ms (bench_incremental).
        thresholds = gc.get_threshold()
        gc.set_threshold(max(thresholds[0], YOUNG_GC_THRESHOLD), *thresholds[1:])
        pool = await _start_pool(settings, services, host_pool)
        app.state.validation_pool = pool
        if services.database.engine.dialect.name != "postgresql":
            # SQLite: this process runs campaign jobs; pick up those a killed one left.
            campaign_routes.start_runner(app)
        # Password hashes in a low-priority process with a bounded queue (store/hashing.py).
        HASHER.use_processes()
        try:
            yield
        finally:
            gc.set_threshold(*thresholds)
            HASHER.stop_processes()
            # Every live rehearsal's viser server (threads and port) ends with the app.
            hub.shutdown()
            runner = getattr(app.state, "campaign_runner", None)
            if runner is not None:
                runner.close()
            if pool is not None:
                services.reports.use_pool(None)
                pool.shutdown()

    return lifespan


async def _start_pool(settings: Settings, services: AppServices,
                      host_pool: HostPoolAddress | None) -> ValidationPools | None:
    """A running server validates in processes of its own (validation_pool.py); an app
    driven without its lifespan (in-process test clients) validates in its threads."""
    pool = _validation_pool(settings, host_pool)
    if pool is not None:
        services.reports.use_pool(pool.validate, pool.validate_parts)
        # Serve once the processes have warmed up (a few seconds), so that the first
        # validation is a warm one; a warm-up slower than WARM_WAIT_S is not waited for.
        await anyio.to_thread.run_sync(pool.wait_warm, WARM_WAIT_S)
    return pool


def _include_routes(app: FastAPI) -> None:
    """The health route and every router, in the order the OpenAPI document lists them."""
    # Taken at start, so that it names the checks this process loaded even if the files are
    # replaced under a running server (verify.fingerprint).
    checker = fingerprint.checker_fingerprint()

    @app.get("/api/health", operation_id="health", tags=["system"],
             openapi_extra={"x-roles": ["anonymous"]})
    async def health() -> dict[str, str]:  # on the event loop: busy worker threads cannot delay it
        """Liveness: the app answers and knows its version and the fingerprint of its checks
        (`checker`, as in its reports and approval statements)."""
        return {"status": "ok", "version": __version__, "checker": checker}

    for module in (auth, client_config, missions, admin, vehicles, procedures, standing,
                   charts, planning, approvals, document, log_witness):
        app.include_router(module.router)
    app.include_router(rehearsals.router)
    app.include_router(rehearsals.viewer)
    app.include_router(export_routes.router)
    app.include_router(execution_routes.router)
    app.include_router(campaign_routes.router)


def _serve_frontend(app: FastAPI, dist: Path) -> None:
    """Serve the built browser app, falling back to index.html for client-side routes."""
    index = dist / "index.html"

    # HEAD as well as GET: monitors and link checkers ask with HEAD (it answered 405).
    @app.api_route("/{path:path}", methods=["GET", "HEAD"], include_in_schema=False)
    def spa(path: str) -> Response:
        if path.startswith("api/") or path == "api":
            return problems.problem(404, f"no API route /{path}")
        if not index.is_file():
            return JSONResponse({"detail": "the browser app is not built; run "
                                 "./scripts/build-frontend (the API is at /api/docs)"},
                                status_code=503)
        # A NUL is no file name: resolve() raises on it (a 500 for any GET /%00).
        candidate = (dist / path).resolve() if "\x00" not in path else index
        if path and candidate.is_file() and candidate.is_relative_to(dist.resolve()):
            # Built assets carry a content hash in their names: cache them for good.
            immutable = path.startswith("assets/")
            return FileResponse(candidate, headers={
                "Cache-Control": "public, max-age=31536000, immutable" if immutable
                else "no-cache"})
        return FileResponse(index, headers={"Cache-Control": "no-cache"})
