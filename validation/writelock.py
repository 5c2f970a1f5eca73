"""One writer at a time: the lock of an atlas store or of a golden suite (shared by ``atlas``, ``case`` and
anything else that writes a folder of results another run may be writing: ``fuzz``'s suite of findings).

The lock is a file: for an atlas store ``STORE.lock`` beside the store (``atlas.zarr.lock`` next to
``atlas.zarr``: beside it, not in it, so that it exists before the store is created and survives
``--overwrite``, which deletes the store; :func:`lock_path`); for a suite ``SUITE/suite.lock`` inside it
(:func:`suite_lock`: the suite's own file, a name no case id may take).  A writer holds an exclusive ``fcntl.flock`` on it for its whole run and writes into it who
it is (one JSON line: pid, host, start time, command).  The operating system releases a ``flock`` when
its holder dies, however it dies (SIGKILL included), so:

* a second writer (a second command on the store, ``--overwrite`` included, or the same command started
  twice on a new store; two ``case`` runs into one suite) finds the lock held and is refused with
  :class:`StoreBusy`, one line naming the store (or suite) and the holder -- it never waits;
* a writer that ended normally (or by Ctrl-C on the command line) removes the file; a file found with a holder in it but no ``flock`` on it
  is the **stale lock** of a run that was killed: it is taken over, and ``StoreLock.stale`` says
  whose it was (the command line prints a note).

The descriptor is not inherited by child processes (Python opens files non-inheritable, PEP 446), so a
Dask worker never keeps the lock alive after its client is gone.  On a file system without ``flock``
support the run goes on without a lock, with ``StoreLock.unsupported`` set (a note on the command
line): a second writer is then not detected.
"""

from __future__ import annotations

import contextlib
import datetime
import errno
import fcntl
import json
import os
import socket
import sys
from pathlib import Path

from . import interrupt

#: The lock file of a suite, inside it (:func:`suite_lock`).
SUITE_LOCK_NAME = "suite.lock"


class StoreBusy(RuntimeError):
    """Another process holds the store's lock (one line naming the store and the holder)."""


def lock_path(store: str) -> Path:
    """The lock file of the atlas store at ``store``: ``STORE.lock`` beside it."""
    p = Path(os.path.abspath(store)) if Path(store).name in ("", ".", "..") else Path(store)
    return p.with_name(p.name + ".lock") if p.name else p / "atlas.lock"


def holder_text(info: dict) -> str:
    """``pid 123 on host h since 2026-11-27T11:40:02Z (gear-rattle atlas ...)`` from a lock record."""
    cmd = str(info.get("command", ""))
    cmd = cmd if len(cmd) <= 160 else cmd[:157] + "..."
    return f"pid {info.get('pid', '?')} on host {info.get('host', '?')} since {info.get('started', '?')}" + (
        f" ({cmd})" if cmd else ""
    )


def _record(command: str | None) -> dict:
    return {
        "pid": os.getpid(),
        "host": socket.gethostname(),
        "started": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "command": command if command is not None else " ".join([Path(sys.argv[0]).name, *sys.argv[1:]]),
    }


def _read(fd: int) -> dict | None:
    """The record in an open lock file (None: empty or unreadable)."""
    try:
        text = os.pread(fd, 4096, 0).decode("utf-8", "replace").strip()
        info = json.loads(text) if text else None
    except (OSError, ValueError):
        return {"pid": "?", "host": "?", "started": "?", "command": "(unreadable lock record)"} if text else None
    return info if isinstance(info, dict) else None


class StoreLock:
    """The exclusive lock of the atlas store at ``store`` (a context manager; :meth:`acquire` never waits).

    ``path``: the lock file (default :func:`lock_path`, beside the store); ``what``: the word messages use
    for what it guards (``store``, ``suite``).  Attributes after :meth:`acquire`: ``stale`` (the record of
    a killed run whose lock was taken over, or None) and ``unsupported`` (the file system refused
    ``flock``: no lock is held).
    """

    def __init__(self, store: str, command: str | None = None, *, path: str | Path | None = None, what: str = "store"):
        self.store = str(store)
        self.path = lock_path(store) if path is None else Path(path)
        self.command = command
        self.what = what
        self.fd: int | None = None
        self.stale: dict | None = None
        self.unsupported: str | None = None

    @property
    def held(self) -> bool:
        return self.fd is not None or self.unsupported is not None

    def acquire(self) -> StoreLock:
        """Take the lock (:class:`StoreBusy` if another process holds it; ``OSError`` if the lock file
        cannot be created)."""
        if self.held:
            return self
        self.path.parent.mkdir(parents=True, exist_ok=True)
        for _ in range(100):  # the file can be removed by its holder between open and flock: open it again
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as e:
                holder = _read(fd)
                os.close(fd)
                if e.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                    who = holder_text(holder) if holder else "another process (it is starting)"
                    raise StoreBusy(
                        f"{self.what} {self.store!r} is in use by another writer: {who}; its lock is "
                        f"{str(self.path)!r}: wait until it ends"
                    ) from None
                self.unsupported = f"{e.strerror or e}"  # e.g. ENOLCK, EOPNOTSUPP: no flock on this file system
                return self
            try:
                same = os.fstat(fd).st_ino == os.stat(self.path).st_ino
            except FileNotFoundError:
                same = False
            if not same:  # its holder removed it after we opened it: lock the file now at the path
                os.close(fd)
                continue
            self.stale = _read(fd)  # a record without a flock: its writer was killed
            self.fd = fd
            interrupt.CLEANUP.append(str(self.path))  # Ctrl-C or SIGTERM on the command line removes it too
            try:
                os.ftruncate(fd, 0)
                os.pwrite(fd, (json.dumps(_record(self.command)) + "\n").encode(), 0)
            except OSError as e:  # e.g. the disk is full: no lock held, no lock file left
                self.stale = None
                self.release()
                raise OSError(e.errno, e.strerror, str(self.path)) from None  # the message names the lock file
            return self
        raise StoreBusy(f"{self.what} {self.store!r}: its lock {str(self.path)!r} keeps changing: another writer")

    def release(self) -> None:
        """Remove the lock file and release the lock (nothing if not held)."""
        fd, self.fd = self.fd, None
        self.unsupported = None
        if fd is None:
            return
        with contextlib.suppress(ValueError):
            interrupt.CLEANUP.remove(str(self.path))
        try:
            os.unlink(self.path)  # while still locked: a waiter that opened it retries on the new file
        except OSError:
            pass
        os.close(fd)

    def __enter__(self) -> StoreLock:
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()


def suite_lock(suite: str | Path, command: str | None = None) -> StoreLock:
    """The lock of the golden suite folder ``suite`` (``SUITE/suite.lock``, :data:`SUITE_LOCK_NAME`), not
    yet taken: every writer of a suite (``case``, ``fuzz``'s findings) holds it while it writes."""
    return StoreLock(str(suite), command, path=Path(suite) / SUITE_LOCK_NAME, what="suite")


__all__ = [
    "StoreBusy",
    "lock_path",
    "holder_text",
    "StoreLock",
    "SUITE_LOCK_NAME",
    "suite_lock",
]
