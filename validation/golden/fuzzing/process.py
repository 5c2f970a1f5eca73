"""The implementation as a process that ``gear-rattle fuzz`` owns (docs/reference/golden_commands.md, "Fuzzing an
implementation": what a kill leaves).

* **Its work folder** (:class:`WorkFolder`): ``$TMPDIR/gear-rattle-fuzz-XXXXXXXX/``, holding the cases
  given to the implementation, their certified references and its output folders.  It holds a lock file,
  :data:`LOCK_NAME`, locked (``flock``) for as long as the run lives: the kernel drops the lock when the
  process ends, however it ends.  The folder is removed on every exit -- a normal one, an error, Ctrl-C,
  SIGTERM (the command line's signal handler, :mod:`validation.interrupt`) -- and, after a SIGKILL, by the
  run's watchdog (:mod:`.reaper`) or else by the next run, which removes every work folder whose lock
  it can take (its owner is gone; another run's live folder stays locked) after killing the processes
  marked with it.
* **Its processes** (:meth:`WorkFolder.run`): the implementation runs in a session and process group of
  its own (``start_new_session``), with the environment variable :data:`.reaper.MARKER` naming the
  work folder; when its command returns, outlives ``--timeout`` or the fuzzer's own deadline, or the
  fuzzer stops (an error, Ctrl-C, SIGTERM), the whole group is killed (SIGKILL: grandchildren included)
  and every process carrying the marker (a grandchild that left the group).  Its stdout and stderr go to
  unnamed files (the implementation cannot replace them); the last :data:`KEEP_BYTES` of each are kept.
* **Its output files** (:func:`output_bytes`): read only when every process of the run has ended, and only
  a regular file (a named pipe, a device, a socket, a folder or a symbolic link is a malformed output,
  never waited on), at most :data:`textformat.MAX_BYTES` bytes.
"""

from __future__ import annotations

import errno
import json
import os
import signal
import stat
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from ... import interrupt
from . import reaper
from ..formats.textformat import MAX_BYTES, MalformedFile, MissingFile

#: The prefix of a run's work folder in the temporary directory.
WORK_PREFIX = "gear-rattle-fuzz-"
#: The lock file in a work folder, locked while its run lives (its text names the run, for people).
LOCK_NAME = "owner.lock"
#: A work folder without a lock file (an earlier version of the fuzzer made none) is removed by a later
#: run only when it has not changed for this long (seconds): it cannot tell a live run from a dead one.
UNLOCKED_STALE_S = 86_400.0
#: Bytes kept of the implementation's stdout and of its stderr (their ends).
KEEP_BYTES = 64 * 1024
#: The longest the fuzzer waits for its watchdog to exit at the end of a run.
WATCHDOG_WAIT_S = 5.0


class ImplementationError(Exception):
    """The implementation cannot be started at all (one line): the run stops."""


# ---------------------------------------------------------------------------------------------
# one run of the implementation


def _signal_name(num: int) -> str:
    """``SIGSEGV`` for 11."""
    try:
        return signal.Signals(num).name
    except ValueError:
        return f"signal {num}"


@dataclass
class RunStatus:
    """How one run of the implementation ended: its exit status (negative: the signal that killed it;
    None: still running at the limit, then killed), whether the limit was ``--timeout`` (``timed_out``) or
    the fuzzer's deadline (``cut``: not the implementation's fault), the seconds it took, the ends of its
    stdout and stderr, and how many cases it was given."""

    returncode: int | None
    timed_out: bool = False
    cut: bool = False
    seconds: float = 0.0
    stdout: bytes = b""
    stderr: bytes = b""
    cases: int = 1
    timeout: float = 0.0

    @property
    def ok(self) -> bool:
        return self.returncode == 0

    def describe(self) -> str:
        """``exited with status 101``, ``was killed by signal 11 (SIGSEGV)``, ``did not finish within 3 s
        (--timeout)``."""
        if self.returncode is None:
            if self.cut:
                return f"was stopped after {self.seconds:.3g} s: the fuzzer's time (--budget) was spent"
            return f"did not finish within {self.timeout:g} s (--timeout)"
        if self.returncode < 0:
            return f"was killed by signal {-self.returncode} ({_signal_name(-self.returncode)})"
        return f"exited with status {self.returncode}"

    def as_dict(self) -> dict:
        rc = self.returncode
        return {
            "exit_status": rc if rc is not None and rc >= 0 else None,
            "signal": _signal_name(-rc) if rc is not None and rc < 0 else None,
            "timed_out": self.timed_out,
            "seconds": round(self.seconds, 3),
            "cases_in_run": self.cases,
        }


def _tail(fh) -> bytes:
    """The last :data:`KEEP_BYTES` of an unnamed file the implementation wrote to."""
    try:
        size = os.fstat(fh.fileno()).st_size
        fh.seek(max(0, size - KEEP_BYTES))
        return fh.read(KEEP_BYTES)
    except OSError:
        return b""


# ---------------------------------------------------------------------------------------------
# the work folder


@dataclass
class WorkFolder:
    """The run's work folder and the processes started in it (module docstring); a context manager.
    ``root``: where to make it (default: the temporary directory)."""

    root: Path | None = None
    path: Path = field(init=False)
    groups: set = field(default_factory=set)
    _lock_fd: int = -1
    _watchdog: subprocess.Popen | None = None

    def __enter__(self) -> WorkFolder:
        root = Path(self.root if self.root is not None else tempfile.gettempdir())
        remove_stale(root)
        with interrupt.CLEANUP_LOCK:
            self.path = Path(tempfile.mkdtemp(prefix=WORK_PREFIX, dir=root))
            interrupt.CLEANUP.append(str(self.path))
        try:
            self._lock()
            self._watchdog = _start_watchdog(self.path)
        except BaseException:
            self.__exit__(None, None, None)
            raise
        return self

    def _lock(self) -> None:
        """Create the lock file under a temporary name, lock it, then rename it into place: a later run
        never sees a lock file that is not locked while this run lives."""
        import fcntl

        tmp = self.path / f".{LOCK_NAME}.{os.getpid()}"
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        os.write(fd, (json.dumps({"program": "gear-rattle fuzz", "pid": os.getpid()}) + "\n").encode())
        os.rename(tmp, self.path / LOCK_NAME)
        self._lock_fd = fd

    def __exit__(self, *exc) -> None:
        reaper.kill_all(self.groups, str(self.path))
        for g in list(self.groups):
            self._untrack(g)
        reaper.remove_tree(self.path)
        with interrupt.CLEANUP_LOCK:
            if str(self.path) in interrupt.CLEANUP:
                interrupt.CLEANUP.remove(str(self.path))
        if self._lock_fd >= 0:
            os.close(self._lock_fd)
            self._lock_fd = -1
        if self._watchdog is not None:
            _stop_watchdog(self._watchdog)
            self._watchdog = None

    def _track(self, pgid: int) -> None:
        self.groups.add(pgid)
        interrupt.PROCESS_GROUPS.append(pgid)
        self._tell(f"+{pgid}")

    def _untrack(self, pgid: int) -> None:
        self.groups.discard(pgid)
        if pgid in interrupt.PROCESS_GROUPS:
            interrupt.PROCESS_GROUPS.remove(pgid)
        self._tell(f"-{pgid}")

    def _tell(self, line: str) -> None:
        w = self._watchdog
        if w is not None and w.stdin is not None:
            try:
                w.stdin.write((line + "\n").encode())
                w.stdin.flush()
            except OSError:  # the watchdog is gone: the next run's sweep is left
                pass

    def run(self, command: list[str], cases_dir: Path, out_dir: Path, timeout: float, limit: float | None) -> RunStatus:
        """Run ``COMMAND CASES_DIR OUT_DIR`` in its own process group; wait at most ``timeout`` seconds
        (``--timeout``) or ``limit`` (the fuzzer's deadline) if smaller; then kill whatever of it is left
        (module docstring).  :class:`ImplementationError` when it cannot be started."""
        wait = timeout if limit is None else max(0.0, min(timeout, limit))
        env = {**os.environ, reaper.MARKER: str(self.path)}
        with tempfile.TemporaryFile(dir=self.path) as out, tempfile.TemporaryFile(dir=self.path) as err:
            t0 = time.monotonic()
            try:
                proc = subprocess.Popen(
                    [*command, str(cases_dir), str(out_dir)],
                    stdin=subprocess.DEVNULL,
                    stdout=out,
                    stderr=err,
                    start_new_session=True,
                    env=env,
                )
            except OSError as e:
                raise ImplementationError(
                    f"cannot start the implementation {command[0]!r}: {e.strerror or e}"
                ) from None
            self._track(proc.pid)
            rc: int | None = None
            try:
                rc = proc.wait(wait)
            except subprocess.TimeoutExpired:
                pass
            finally:
                reaper.kill_all([proc.pid], str(self.path))
                try:
                    proc.wait(reaper.GONE_WAIT_S)  # reaped
                except subprocess.TimeoutExpired:  # a process the system would not kill (uninterruptible)
                    pass
                self._untrack(proc.pid)
            seconds = time.monotonic() - t0
            late = rc is None
            return RunStatus(
                rc,
                timed_out=late and wait >= timeout,
                cut=late and wait < timeout,
                seconds=seconds,
                stdout=_tail(out),
                stderr=_tail(err),
                timeout=timeout,
            )


def _start_watchdog(work: Path) -> subprocess.Popen | None:
    """The run's watchdog (:mod:`.reaper`), in a session of its own; None where it cannot start (the
    next run's sweep is left)."""
    try:
        return subprocess.Popen(
            [sys.executable, "-I", "-S", reaper.__file__, str(work)],
            stdin=subprocess.PIPE,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
    except OSError:
        return None


def _stop_watchdog(w: subprocess.Popen) -> None:
    try:
        if w.stdin is not None:
            w.stdin.close()
        w.wait(WATCHDOG_WAIT_S)
    except (OSError, subprocess.TimeoutExpired):
        w.kill()
        w.wait()


def remove_stale(root: Path) -> list[Path]:
    """Remove the work folders in ``root`` left by runs that are gone (a SIGKILL, a machine that stopped):
    those whose lock file this process can lock, after killing the processes marked with them; those
    without a lock file only after :data:`UNLOCKED_STALE_S` unchanged.  Another user's folders, links and
    live runs' folders are left alone.  Returns what was removed."""
    import fcntl

    removed: list[Path] = []
    try:
        entries = [e for e in os.scandir(root) if e.name.startswith(WORK_PREFIX)]
    except OSError:
        return removed
    for entry in entries:
        try:
            st = entry.stat(follow_symlinks=False)
        except OSError:
            continue
        if not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid():
            continue
        try:
            fd = os.open(Path(entry.path) / LOCK_NAME, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
        except FileNotFoundError:
            if time.time() - st.st_mtime > UNLOCKED_STALE_S:
                reaper.kill_all([], entry.path)
                reaper.remove_tree(entry.path)
                removed.append(Path(entry.path))
            continue
        except OSError:
            continue
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                continue
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as e:
                if e.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                    continue  # a live run
                raise
            reaper.kill_all([], entry.path)
            reaper.remove_tree(entry.path)
            removed.append(Path(entry.path))
        except OSError:
            continue
        finally:
            os.close(fd)
    return removed


# ---------------------------------------------------------------------------------------------
# reading what it wrote

_KINDS = (
    (stat.S_ISFIFO, "a named pipe"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISLNK, "a symbolic link"),
)


def _not_regular(mode: int) -> str | None:
    return None if stat.S_ISREG(mode) else next((what for test, what in _KINDS if test(mode)), "not a file")


def output_bytes(path: Path) -> bytes:
    """The bytes of an output file of the implementation (its processes have ended): :class:`MissingFile`
    when there is none, :class:`MalformedFile` (one line) when it is not a regular file or is larger than
    :data:`textformat.MAX_BYTES` -- never opened where opening could wait.  (The one place the fuzzer reads
    an implementation's output; the suite's own reader of regular files with limits may replace it.)"""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        raise MissingFile(f"{path}: missing file") from None
    except OSError as e:
        raise MalformedFile(f"{path}: cannot read: {e.strerror or e}") from None
    what = _not_regular(st.st_mode)
    if what is not None:
        raise MalformedFile(f"{path}: {what}, not a regular file (allowed: a regular file)")
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError as e:
        raise MalformedFile(f"{path}: cannot read: {e.strerror or e}") from None
    with os.fdopen(fd, "rb") as fh:
        what = _not_regular(os.fstat(fh.fileno()).st_mode)
        if what is not None:
            raise MalformedFile(f"{path}: {what}, not a regular file (allowed: a regular file)")
        data = fh.read(MAX_BYTES + 1)
    if len(data) > MAX_BYTES:
        raise MalformedFile(f"{path}: file larger than {MAX_BYTES} bytes (the limit of the format)")
    return data
