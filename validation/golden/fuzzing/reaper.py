"""What ``gear-rattle fuzz`` leaves behind when it is killed: nothing.  Standard library only.

The fuzzer starts the implementation in a session (process group) of its own, with the environment
variable :data:`MARKER` naming the run's work folder; it kills the group (and every process carrying the
marker: a grandchild that left the group with ``setsid``) after each run, on a timeout, on Ctrl-C and on
SIGTERM (:mod:`.process`).  A SIGKILL of the fuzzer runs no code of its own, so each run also starts
this module as a **watchdog** (``python -I -S fuzz_reaper.py WORK``, in a session of its own, so that
the terminal's Ctrl-C and a kill of the fuzzer's group do not reach it): the fuzzer tells it, on its
standard input, each process group it starts (``+PGID``) and ends (``-PGID``); when that input ends --
the fuzzer has exited, however it ended -- the watchdog kills the groups still listed and the marked
processes, removes the work folder (when the fuzzer has not) and exits.

The functions below are also what the fuzzer uses itself (one implementation of each).
"""

from __future__ import annotations

import os
import shutil
import signal
import sys
import time

#: The environment variable that marks the implementation's processes: its value is the run's work folder.
MARKER = "GEAR_RATTLE_FUZZ_WORK"
#: The longest a kill waits for the killed processes to be gone (they cannot run again once killed; this
#: waits for the kernel to finish them, so that the work folder is removed after their last write).
GONE_WAIT_S = 2.0


def _stat_fields(pid: str) -> list[str] | None:
    """``[state, ppid, pgrp, session, ...]`` of ``/proc/PID/stat`` (None when the process is gone)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            text = fh.read().decode("ascii", "replace")
    except OSError:
        return None
    return text.rsplit(")", 1)[-1].split()


def _pids() -> list[str]:
    try:
        return [p for p in os.listdir("/proc") if p.isdigit() and int(p) != os.getpid()]
    except OSError:  # no /proc (not Linux): only the process groups are killed
        return []


def marked_processes(work: str) -> list[int]:
    """The live processes (not zombies) whose environment carries ``MARKER=work`` (Linux ``/proc``; the
    processes of other users are not readable and not listed)."""
    want = f"{MARKER}={work}".encode()
    out = []
    for pid in _pids():
        try:
            with open(f"/proc/{pid}/environ", "rb") as fh:
                env = fh.read()
        except OSError:
            continue
        if want in env.split(b"\0"):
            st = _stat_fields(pid)
            if st and st[0] != "Z":
                out.append(int(pid))
    return out


def group_members(pgid: int) -> list[int]:
    """The live processes (not zombies) of process group ``pgid``."""
    if not os.path.isdir("/proc"):
        try:
            os.killpg(pgid, 0)
        except OSError:
            return []
        return [pgid]
    out = []
    for pid in _pids():
        st = _stat_fields(pid)
        if st and len(st) > 2 and st[2] == str(pgid) and st[0] != "Z":
            out.append(int(pid))
    return out


def kill_all(groups, work: str | None = None, wait: float = GONE_WAIT_S) -> None:
    """SIGKILL every process group of ``groups`` and every process marked with ``work``, then wait (at
    most ``wait`` seconds) until none of them is alive (a zombie waiting to be reaped counts as gone)."""
    groups = [int(g) for g in groups]
    for g in groups:
        try:
            os.killpg(g, signal.SIGKILL)
        except OSError:
            pass
    end = time.monotonic() + wait
    while True:
        left = marked_processes(work) if work else []
        for p in left:
            try:
                os.kill(p, signal.SIGKILL)
            except OSError:
                pass
        alive = left + [p for g in groups for p in group_members(g)]
        if not alive or time.monotonic() > end:
            return
        time.sleep(0.01)


def remove_tree(path) -> None:
    """Remove a folder the implementation wrote in, whatever it did to the permissions of its subfolders
    (each is made writable and searchable again where a removal fails); errors are ignored."""

    def again(func, p, exc_info) -> None:
        try:
            os.chmod(os.path.dirname(p), 0o700)
            if os.path.isdir(p) and not os.path.islink(p):
                os.chmod(p, 0o700)
                shutil.rmtree(p, ignore_errors=True)
            else:
                func(p)
        except OSError:
            pass

    shutil.rmtree(path, onerror=again)


def main(argv: list[str]) -> int:
    """The watchdog (module docstring): ``WORK`` the run's work folder."""
    (work,) = argv
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    groups: set[int] = set()
    try:
        for line in sys.stdin:
            word = line.strip()
            if word[:1] in "+-" and word[1:].isdigit():
                (groups.add if word[0] == "+" else groups.discard)(int(word[1:]))
    except (OSError, ValueError):
        pass
    kill_all(groups, work)
    remove_tree(work)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
