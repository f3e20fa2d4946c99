"""Several server processes on one port under gunicorn, with uvicorn workers and `reuse_port`.

gunicorn's master forks the workers, replaces one that dies, stops the server when one fails
to boot or load the app, and on SIGTERM lets them finish their requests (graceful_timeout).
With `reuse_port` (gunicorn 27: `Arbiter.spawn_worker`) each worker binds and listens on a
socket of its own after the fork, so the kernel spreads new connections over the processes;
the master holds none. The keep-alive timeout is uvicorn's (5 s), not gunicorn's 2 s.

Two things are added (they replace the home-made supervisor, web/workers.py, that did the
same with uvicorn processes of its own; bench_api measured gunicorn as good):

* each worker leads a process group holding what it starts (the forkserver and its hashing and
  validation processes); when the master reaps a worker it SIGKILLs what is left of the group,
  since a worker killed outright would leave them orphaned and holding the resource tracker;
* the master keeps a bound, non-listening SO_REUSEPORT socket on the port for as long as it
  runs: a taken port is refused before any worker starts (with its reason), port 0 is resolved
  once for all workers, and no other process can take the port meanwhile.

The app comes from a factory the caller hands over (the command line's settings in a closure):
the master holds it and each worker, forked from the master, calls it after the fork. Nothing
travels through environment variables.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import socket
import sys
from collections.abc import Callable
from typing import Any

from gunicorn.app.base import BaseApplication

logger = logging.getLogger("countersign.workers")

STOP_GRACE = 30  # seconds a stopping process may take to finish its requests
KEEP_ALIVE = 5  # uvicorn's default, the single-process server's


def reuse_port_available() -> bool:
    return hasattr(socket, "SO_REUSEPORT")


def _reservation(host: str, port: int) -> socket.socket:
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    try:
        sock.bind((host, port))
    except OSError:
        sock.close()
        raise
    return sock


def _post_fork(server: Any, worker: Any) -> None:
    with contextlib.suppress(OSError):
        os.setpgrp()


def _child_exit(server: Any, worker: Any) -> None:
    """SIGKILL what is left of the process group of a reaped worker."""
    with contextlib.suppress(OSError):  # the group is gone already
        os.killpg(worker.pid, signal.SIGKILL)


class _Application(BaseApplication):  # type: ignore[misc]
    def __init__(self, factory: Callable[[], Any], options: dict[str, Any]) -> None:
        self.factory = factory
        self.options = options
        super().__init__()

    def load_config(self) -> None:
        for key, value in self.options.items():
            self.cfg.set(key, value)

    def load(self) -> Any:
        # In each worker, after the fork (gunicorn does not preload the app here).
        return self.factory()


def serve_workers(app: Callable[[], Any], *, host: str, port: int, workers: int,
                  log_level: str, reuse_port: bool = True) -> int:
    """Run `workers` processes of the app that `app()` builds, called in each of them, on
    host:port; with reuse_port False they share the master's one listening socket (a
    baseline only)."""
    if not logging.getLogger().handlers:
        logging.basicConfig(stream=sys.stderr, level=logging.INFO,
                            format="%(levelname)s:     %(message)s")
    if not (reuse_port and reuse_port_available()):  # gunicorn's shared socket
        reservation = None
    else:
        try:
            reservation = _reservation(host, port)
        except OSError as error:
            logger.error("cannot listen on %s:%s: %s", host, port, error.strerror)
            return 1
        port = reservation.getsockname()[1]
    bind = f"[{host}]:{port}" if ":" in host else f"{host}:{port}"
    options = {
        "bind": [bind],
        "workers": workers,
        "worker_class": "uvicorn_worker.UvicornWorker",
        "reuse_port": reservation is not None,
        "keepalive": KEEP_ALIVE,
        "graceful_timeout": STOP_GRACE,
        "loglevel": log_level,
        "post_fork": _post_fork,
        "child_exit": _child_exit,
        "proc_name": "countersign",
        "control_socket_disable": True,  # one fixed path per user: instances would clash
    }
    try:
        _Application(app, options).run()  # returns or exits with the master's status
    except SystemExit as stop:
        return stop.code if isinstance(stop.code, int) else 1
    finally:
        if reservation is not None:
            reservation.close()
    return 0
