"""Pool processes that end with the server process that started them.

A ProcessPoolExecutor worker started through the forkserver is the forkserver's child, not the
server's, and it holds both ends of its own call queue: when the server is SIGKILLed (the OOM
killer, `kill -9`) the worker never reads end-of-file and waits forever, and it keeps the
forkserver (through the forkserver's liveness pipe) and the resource tracker alive with it. A
parent-death signal cannot help, since the parent is the forkserver. So each pool process
watches its owner's pid and exits once the owner has ended.
"""

from __future__ import annotations

import os
import select
import threading
import time

_POLL_S = 1.0


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _wait_for_end(pid: int) -> None:
    try:
        handle = os.pidfd_open(pid)
    except ProcessLookupError:
        return
    except OSError:  # no pidfd (old kernel, seccomp): poll instead
        while _alive(pid):
            time.sleep(_POLL_S)
        return
    try:
        select.select([handle], [], [])  # a pidfd turns readable when its process ends
    finally:
        os.close(handle)


def end_with(owner_pid: int) -> None:
    """From now on, this process exits as soon as the process `owner_pid` has ended."""

    def watch() -> None:
        _wait_for_end(owner_pid)
        # Nothing of the pool's work can reach the owner any more; end without cleanup,
        # which would wait on queues nobody reads.
        os._exit(0)

    threading.Thread(target=watch, name=f"end-with-{owner_pid}", daemon=True).start()
