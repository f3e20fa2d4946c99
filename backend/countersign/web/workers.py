"""Several server processes on one port, each with its own listening socket (SO_REUSEPORT).

uvicorn's own `--workers` shares one listening socket between its processes: whichever process
wakes first accepts a burst of connections, and with keep-alive clients (browsers, the API
benchmark's 50 clients) one process ends up serving most of the load on one core while the
other idles (measured: 86% / 14% of the samples). With a socket per process the kernel spreads
new connections over the processes by their addresses instead.

The supervisor keeps a bound, non-listening socket on the port for as long as it runs: only
listening sockets are handed connections, and the port cannot be taken by another account's
process meanwhile. A process that dies is started again; one that fails while starting stops
the whole server (it would fail the same way again).
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import os
import signal
import socket
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.process import BaseProcess
from multiprocessing.synchronize import Event as EventType

import uvicorn

logger = logging.getLogger("countersign.workers")

RESTARTS_PER_MINUTE = 5  # more, and the server stops: something is wrong with every start
STOP_GRACE = 30.0  # seconds a stopping process may take to finish its requests


def reuse_port_available() -> bool:
    return hasattr(socket, "SO_REUSEPORT")


def _socket(host: str, port: int) -> socket.socket:
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    sock.bind((host, port))
    return sock


class _Server(uvicorn.Server):
    """uvicorn's server, telling the supervisor once it serves."""

    def __init__(self, config: uvicorn.Config, serving: EventType) -> None:
        super().__init__(config)
        self.serving = serving

    async def startup(self, sockets: list[socket.socket] | None = None) -> None:
        await super().startup(sockets)
        if self.started:
            self.serving.set()


def _run_worker(config: uvicorn.Config, serving: EventType) -> None:
    # A process group of its own, holding everything this process starts (the forkserver and
    # its hashing and validation processes): the supervisor ends the group once the process
    # has ended. A process killed outright (SIGKILL, out of memory) leaves its forkserver and
    # pool processes running, orphaned, and they hold the supervisor's resource-tracker pipe
    # open, so that the tracker too outlived the server's SIGTERM forever (issue 15).
    with contextlib.suppress(OSError):
        os.setpgrp()
    # Bound but not yet listening: uvicorn listens (asyncio's create_server) only after the
    # app has loaded and its startup has run. A replacement process that listened at once was
    # handed its share of new connections while it was still importing and migrating, seconds
    # on a busy machine, and they waited or were reset if it failed (issue 15).
    sock = _socket(config.host, config.port)
    _Server(config, serving).run(sockets=[sock])


@dataclass
class _Worker:
    process: BaseProcess
    serving: EventType


def _end_group(pid: int | None) -> None:
    """SIGKILL what is left of the process group of an ended server process `pid`."""
    if pid is None:
        return
    with contextlib.suppress(OSError):  # the group is gone already (or never was its own)
        if os.getpgid(pid) != pid:  # a zombie's group: only ours if it made it a leader
            return
    with contextlib.suppress(OSError):
        os.killpg(pid, signal.SIGKILL)


class Supervisor:
    def __init__(self, config: uvicorn.Config, workers: int) -> None:
        self.config = config
        self.workers = workers
        self.context = multiprocessing.get_context("spawn")
        self.stopping = threading.Event()
        self.processes: list[_Worker] = []
        self.restarts: list[float] = []

    def _start(self) -> _Worker:
        serving = self.context.Event()
        process = self.context.Process(target=_run_worker, args=(self.config, serving),
                                       name="countersign-worker")
        process.start()
        logger.info("started server process %s", process.pid)
        return _Worker(process, serving)

    def _stop_all(self) -> None:
        for worker in self.processes:
            if worker.process.is_alive():
                worker.process.terminate()  # SIGTERM: uvicorn finishes open requests, exits
        deadline = time.monotonic() + STOP_GRACE
        for worker in self.processes:
            worker.process.join(max(0.0, deadline - time.monotonic()))
            if worker.process.is_alive():
                worker.process.kill()
                worker.process.join()
            _end_group(worker.process.pid)

    def _replace(self, index: int) -> bool:
        """Start a process in place of a dead one; False when the server must stop."""
        dead = self.processes[index]
        _end_group(dead.process.pid)
        if not dead.serving.is_set():
            logger.error("server process %s failed to start (exit code %s); stopping",
                         dead.process.pid, dead.process.exitcode)
            return False
        now = time.monotonic()
        self.restarts = [at for at in self.restarts if now - at < 60] + [now]
        if len(self.restarts) > RESTARTS_PER_MINUTE:
            logger.error("server processes died %d times within a minute; stopping",
                         len(self.restarts))
            return False
        logger.warning("server process %s died (exit code %s); starting another",
                       dead.process.pid, dead.process.exitcode)
        self.processes[index] = self._start()
        return True

    def run(self) -> int:
        """Serve until SIGINT or SIGTERM; the exit status of the server."""
        try:
            reservation = _socket(self.config.host, self.config.port)
        except OSError as error:
            logger.error("cannot listen on %s:%s: %s", self.config.host, self.config.port,
                         error.strerror)
            return 1
        # Port 0 asks for any free port: the processes share the one found here.
        self.config.port = reservation.getsockname()[1]
        handlers: dict[signal.Signals, Callable[..., object] | int | None] = {}
        for signum in (signal.SIGINT, signal.SIGTERM):
            handlers[signum] = signal.signal(signum, lambda *_: self.stopping.set())
        status = 0
        try:
            self.processes = [self._start() for _ in range(self.workers)]
            while not self.stopping.wait(0.5):
                dead = [i for i, w in enumerate(self.processes) if not w.process.is_alive()]
                if not all(self._replace(index) for index in dead):
                    status = 1
                    break
        finally:
            self._stop_all()
            reservation.close()
            for signum, handler in handlers.items():
                signal.signal(signum, handler)
        return status


def serve_workers(app: str, *, host: str, port: int, workers: int, log_level: str) -> int:
    """Run `workers` processes of the app factory `app` ("module:function") on host:port."""
    config = uvicorn.Config(app, factory=True, host=host, port=port, log_level=log_level)
    if not reuse_port_available():  # not on this platform: uvicorn's shared socket
        uvicorn.run(app, factory=True, host=host, port=port, workers=workers,
                    log_level=log_level)
        return 0
    if not logging.getLogger().handlers:
        logging.basicConfig(stream=sys.stderr, level=logging.INFO,
                            format="%(levelname)s:     %(message)s")
    return Supervisor(config, workers).run()
