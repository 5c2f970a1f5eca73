"""The one output writer: every file a command or the report writes goes through :func:`write_atomic`.

**A file** is written to a temporary name beside its target (same directory, so the same file system),
flushed to disk (``fsync``) and renamed over the target with :func:`os.replace`: a kill at any moment
leaves either the earlier file or the new one, whole, never an empty or cut file.  The temporary name
is ``.<target name>.partial-<pid>-<8 hex digits>`` (:func:`staging_name`).

**A command's outputs are one set** (:func:`outputs`, opened by the command line around every command):
while it runs, each file waits at its temporary name; when the command has finished, all of them are
renamed into place together (:meth:`Outputs.commit`, a few milliseconds) under
:data:`validation.interrupt.CLEANUP_LOCK`, the lock the Ctrl-C/SIGTERM handler takes before it removes the
temporary files -- so a signal gives every earlier file or every new one, and a failure (an error, a
full disk) leaves every earlier file as it was.  Without an open set (the library), a file is renamed
into place as soon as it is written.

**A folder of outputs** (``--out DIR`` of ``report``, ``basins``, ``uncertainty``, ``transients``,
``check --self``): each file is moved in on its own (as above), never the folder: ``DIR`` may hold
files of the user's, in ``figures/`` and ``data/`` too, and a command replaces only the files it
writes.  With the files, the set writes ``DIR/<command>.manifest.json`` naming the run (command line,
start time, process, host) and each file it wrote (bytes, SHA-256) -- first with ``"complete": false``,
then, once every file is in place, ``true``; only a SIGKILL inside those milliseconds leaves
``false``, which says that the folder mixes two runs (:func:`read_manifest`).  The report is computed in
a staging folder (:func:`staged`; inside ``DIR`` when it exists, beside it otherwise) whose files are
then moved in the same way.

**Debris**: a SIGKILL leaves the temporary files (or a report's staging folder) behind.  The next run
that writes the same target removes them (:func:`remove_debris`): only entries named by the pattern
above for that very target, older than the run, and whose process is gone (a concurrent run's files
are left alone); never a file of the user's.  The staging folders of earlier versions
(``.<DIR>.partial-<8 characters>``, from ``tempfile.mkdtemp``) are recognised as well.

**Special targets** (the one rule of every command, the report's staged files included): a symbolic link
is followed (the file it points to is replaced atomically, the link stays) -- in a folder of outputs the
manifest lists the file under the name asked for, with ``written_to``, the real path written, where a
link led elsewhere; a target that exists and is not a regular file (``/dev/null``, a named pipe, a
terminal) is written in place -- there is no earlier content to keep.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import secrets
import shutil
import socket
import stat
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO

from .. import interrupt

#: The temporary (staging) names this writer gives: ``.<base>.partial-<pid>-<8 hex>`` (and the
#: ``.<base>.partial-<8 characters>`` of ``tempfile.mkdtemp`` that earlier versions gave the report).
STAGING_NAME = re.compile(r"^\.(?P<base>.+)\.partial-(?:(?P<pid>\d+)-[0-9a-f]{8}|[a-z0-9_]{8})$")
#: A target's name is cut to this many bytes in its temporary name (the whole must stay within the
#: 255 bytes a file system allows a name, and a target may have a name of up to 255 bytes itself).
BASE_BYTES = 200
#: The manifest of a folder of outputs: ``<command>.manifest.json`` (``report.manifest.json``).
MANIFEST = "{}.manifest.json"
#: errno values of a device that failed (disk full, quota, I/O error, file too large), as opposed to a
#: path the system refuses: the command line's exit status 1 (2 for a refused path); the report stops.
DEVICE_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EIO, errno.EFBIG})
#: The time the process loaded this module: debris must be older than this (or than the set's start).
LOADED = time.time()


# ------------------------------------------------------------------------------------- names and debris


def _base(name: str) -> str:
    raw = name.encode("utf-8", "surrogateescape")
    return raw[:BASE_BYTES].decode("utf-8", "ignore") if len(raw) > BASE_BYTES else name


def staging_name(target_name: str) -> str:
    """A new temporary name for the target ``target_name``: ``.<name>.partial-<pid>-<8 hex digits>``."""
    return f".{_base(target_name)}.partial-{os.getpid()}-{secrets.token_hex(4)}"


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return False  # an earlier process with this number: ours started after the debris was written
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # it exists and belongs to someone else
        return True
    return True


def remove_debris(folder: Path, base: str, since: float | None = None) -> list[Path]:
    """Remove the staging debris of the target named ``base`` in ``folder``: entries whose name matches
    :data:`STAGING_NAME` for that name, modified before ``since`` (default: when this module was
    loaded) and whose process has ended.  Returns what was removed; a file system error is ignored
    (the debris stays, the run goes on)."""
    since = LOADED if since is None else since
    want = _base(base)
    removed: list[Path] = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        m = STAGING_NAME.match(entry.name)
        if not m or m["base"] != want:
            continue
        try:
            st = entry.stat(follow_symlinks=False)
            if st.st_mtime >= since or (m["pid"] is not None and _alive(int(m["pid"]))):
                continue
            if stat.S_ISDIR(st.st_mode):
                shutil.rmtree(entry.path)
            else:
                os.unlink(entry.path)
            removed.append(Path(entry.path))
        except OSError:
            continue
    return removed


# ---------------------------------------------------------------------------------- the set of outputs


class Outputs:
    """The files a command writes, renamed into place together by :meth:`commit` (see the module
    docstring).  ``folder``: its ``--out`` directory, where :meth:`commit` writes the manifest naming
    the run (``label``: the command, e.g. ``report``)."""

    def __init__(
        self,
        label: str = "gear-rattle",
        folder: str | Path | None = None,
        argv: list[str] | None = None,
        merge: bool = False,
    ):
        self.label = label
        self.merge = merge  # the manifest keeps the earlier run's entries of files not written again
        self.folder = Path(folder) if folder is not None else None
        self.argv = list(sys.argv if argv is None else argv)
        self.started = time.time()
        self.pending: list[tuple[Path, Path]] = []  # (temporary file, target)
        self.asked: dict[Path, Path] = {}  # target -> the name the command asked for (a link: where it leads)
        self.stages: list[Path] = []  # staging folders: files written in them are renamed at once
        self.written: list[Path] = []  # targets committed

    def in_stage(self, path: Path) -> bool:
        return any(path == s or s in path.parents for s in self.stages)

    def commit(self) -> list[Path]:
        """Rename every waiting file into place, with the folder's manifest (the lock held: a signal
        waits for it); returns the targets."""
        if not self.pending:
            return []
        pairs, self.pending = self.pending, []
        inside = self._in_folder(pairs)
        try:
            for _, target in pairs:  # every target checked before the first rename
                if target.is_dir() and not target.is_symlink():
                    raise IsADirectoryError(errno.EISDIR, "is a directory (allowed a file)", str(target))
            if inside:  # both manifests written before anything moves (a full disk stops the run here)
                files = _digests(inside)
                if self.merge and self.folder is not None:
                    files = {**(read_manifest(self.folder, self.label) or {}).get("files", {}), **files}
                pairs = [self._manifest(files, complete=False), *pairs, self._manifest(files, complete=True)]
            with _locked():
                for tmp, target in pairs:
                    _replace(tmp, target)
        except BaseException:
            self.pending = [(t, g) for t, g in pairs if t.exists()]
            raise
        for d in {target.parent for _, target in pairs}:
            _fsync_dir(d)
        targets = list(dict.fromkeys(target for _, target in pairs))
        self.written += targets
        return targets

    def _in_folder(self, pairs) -> dict[str, tuple[Path, str | None]]:
        """``{name in the folder: (temporary file, where it is written)}`` of the files asked for inside the
        folder: the name as asked (relative to the folder, links not followed) and, where a link in it
        leads elsewhere (the link rule: followed), the real path written, else None."""
        if self.folder is None:
            return {}
        root, real_root = os.path.abspath(self.folder), os.path.realpath(self.folder)
        out: dict[str, tuple[Path, str | None]] = {}
        for tmp, target in pairs:
            asked = os.path.abspath(self.asked.get(target, target))
            if os.path.commonpath([root, asked]) != root or asked == root:
                continue
            rel = Path(os.path.relpath(asked, root)).as_posix()
            real = os.path.realpath(target)
            same = (
                os.path.commonpath([real_root, real]) == real_root
                and Path(os.path.relpath(real, real_root)).as_posix() == rel
            )
            out[rel] = (tmp, None if same else real)
        return out

    def _manifest(self, files: dict, complete: bool) -> tuple[Path, Path]:
        """The manifest written to its temporary file: ``(temporary file, target)``."""
        from .jsontext import json_text

        assert self.folder is not None
        doc = {
            "command": self.label,
            "argv": self.argv,
            "complete": complete,
            "run": {
                "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(self.started)),
                "pid": os.getpid(),
                "host": socket.gethostname(),
            },
            "files": files,
        }
        return _write_temp(self.folder / MANIFEST.format(self.label), (json_text(doc) + "\n").encode())

    def discard(self) -> None:
        """Remove every waiting temporary file (and staging folder): the earlier outputs stay."""
        with _locked():
            for tmp, _ in self.pending:
                _unlink(tmp)
            self.pending = []
            for s in self.stages:
                shutil.rmtree(s, ignore_errors=True)
                _forget(s)
            self.stages = []


def _digests(inside: dict[str, tuple[Path, str | None]]) -> dict:
    """``{relative name: {bytes, sha256[, written_to]}}`` of the files ``{relative name: (temporary file,
    where a link led it or None)}``."""
    files = {}
    for rel, (tmp, real) in sorted(inside.items()):
        h = hashlib.sha256()
        with open(tmp, "rb") as fh:
            for block in iter(lambda: fh.read(1 << 20), b""):
                h.update(block)
        files[rel] = {"bytes": tmp.stat().st_size, "sha256": h.hexdigest()}
        if real is not None:
            files[rel]["written_to"] = real
    return files


_OPEN: list[Outputs] = []


def current() -> Outputs | None:
    """The set of outputs open now (the command's), or None (the library: files go in at once)."""
    return _OPEN[-1] if _OPEN else None


@contextlib.contextmanager
def outputs(
    label: str = "gear-rattle", folder: str | Path | None = None, argv: list[str] | None = None, merge: bool = False
) -> Iterator[Outputs]:
    """Open a set of outputs (:class:`Outputs`): files written inside wait at their temporary names and
    are renamed into place together when the block ends without an exception
    (:meth:`Outputs.commit`), else removed."""
    tx = Outputs(label, folder, argv, merge)
    _OPEN.append(tx)
    try:
        yield tx
        tx.commit()
    finally:
        _OPEN.remove(tx)
        tx.discard()


def commit_pending() -> None:
    """Rename the open set's waiting files into place now (before a command prints where they are)."""
    tx = current()
    if tx is not None:
        tx.commit()


# ------------------------------------------------------------------------------------------ one file


@contextlib.contextmanager
def _locked() -> Iterator[None]:
    with interrupt.CLEANUP_LOCK:
        yield


def _forget(path: Path) -> None:
    with contextlib.suppress(ValueError):
        interrupt.CLEANUP.remove(str(path))


def _unlink(path: Path) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)
    _forget(path)


def _fsync_dir(folder: Path) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:  # a file system without directory fsync
        pass
    finally:
        os.close(fd)


def _write_temp(
    target: Path, data: bytes | Callable[[IO[bytes]], object], mode: int | None = None
) -> tuple[Path, Path]:
    """Write ``data`` (bytes, or a function filling a binary file) to a new temporary file beside
    ``target``, flushed to disk; returns ``(temporary file, target)``.  The temporary file is in
    :data:`validation.interrupt.CLEANUP` until it is renamed or removed.  An ``OSError`` without a file
    name (a write or fsync on a full disk) is raised again naming the temporary file (messages then name
    the target: :func:`target_of`)."""
    tmp = target.parent / staging_name(target.name)
    with _locked():
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        interrupt.CLEANUP.append(str(tmp))
    try:
        with os.fdopen(fd, "wb") as fh:
            if mode is not None:
                os.fchmod(fh.fileno(), mode)
            if isinstance(data, bytes):
                fh.write(data)
            else:
                data(fh)
            fh.flush()
            os.fsync(fh.fileno())
    except OSError as e:
        _unlink(tmp)
        if e.filename is None:
            raise OSError(e.errno, e.strerror, str(tmp)) from None
        raise
    except BaseException:
        _unlink(tmp)
        raise
    return tmp, target


def target_of(path: str | Path) -> Path:
    """The output a temporary or staged path stands for: ``DIR/.<name>.partial-...`` is ``DIR/<name>``, a
    file in a staging folder (:func:`staged`: inside the output folder or beside it) the file of that name
    in the output folder; any other path is itself."""
    p = Path(path)
    parts = p.parts
    for i in range(len(parts) - 1, -1, -1):
        m = STAGING_NAME.match(parts[i])
        if m:
            parent = Path(*parts[:i]) if i else Path()
            inside = i < len(parts) - 1 and parent.name == m["base"]  # a staging folder inside its output folder
            return target_of((parent if inside else parent / m["base"]).joinpath(*parts[i + 1 :]))
    return p


def _replace(tmp: Path, target: Path) -> None:
    """``os.replace(tmp, target)`` (lock held by the caller); across file systems (a subfolder that is a
    link to another one) a copy beside the target is renamed instead."""
    try:
        os.replace(tmp, target)
    except OSError as e:
        if e.errno != errno.EXDEV:
            raise
        with open(tmp, "rb") as fh:
            copy = _write_temp(target, fh.read())[0]
        os.replace(copy, target)
        _forget(copy)
        _unlink(tmp)
    _forget(tmp)


def resolve_target(path: str | Path) -> tuple[Path, bool]:
    """Where a write to ``path`` goes, and whether it can be atomic: a symbolic link is followed; an
    existing target that is not a regular file (a device, a named pipe) is written in place."""
    p = Path(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        st = None
    except OSError:
        raise
    if st is not None and not stat.S_ISREG(st.st_mode):
        if stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError(errno.EISDIR, "is a directory (allowed a file)", str(p))
        return p, False
    if p.is_symlink():
        return Path(os.path.realpath(p)), True
    return p, True


def write_atomic(path: str | Path, data: bytes | Callable[[IO[bytes]], object]) -> Path:
    """Write a whole file: ``data`` as bytes, or a function that writes the content to the binary file
    it is given.  Atomic (see the module docstring): written beside the target, flushed, renamed --
    at once, or at the end of the open set of outputs (:func:`outputs`).  Parent folders are created.
    Returns ``path``."""
    target, atomic = resolve_target(path)
    if not atomic:
        with open(target, "wb") as fh:
            if isinstance(data, bytes):
                fh.write(data)
            else:
                data(fh)
        return Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    tx = current()
    remove_debris(target.parent, target.name, since=tx.started if tx is not None else None)
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except OSError:
        mode = None
    tmp, _ = _write_temp(target, data, mode)
    if tx is not None and not tx.in_stage(target):
        tx.pending.append((tmp, target))
        tx.asked[target] = Path(path)
    else:
        with _locked():
            _replace(tmp, target)
    return Path(path)


def write_text_atomic(path: str | Path, text: str, encoding: str = "utf-8") -> Path:
    """:func:`write_atomic` of ``text`` (UTF-8 by default)."""
    return write_atomic(path, text.encode(encoding))


# ----------------------------------------------------------------------------------- a staged folder


@contextlib.contextmanager
def staged(out: str | Path, label: str = "report") -> Iterator[Path]:
    """A staging folder for a folder of outputs that is written as a whole before any of it goes in
    (the report: its page embeds its figures): inside ``out`` when it exists, beside it otherwise.  On
    success each file is moved into ``out`` (a file of the same name replaced, nothing else in ``out``
    touched) when the block ends, with ``out``'s manifest (that of the command's set of outputs, or
    ``<label>.manifest.json``); on failure or a signal the staging folder is removed."""
    out = Path(out)
    name = out.resolve().name or "out"
    home = out if out.is_dir() else out.parent
    home.mkdir(parents=True, exist_ok=True)
    tx = current()
    since = tx.started if tx is not None else None
    for folder in {out.parent, out} if out.is_dir() else {out.parent}:
        remove_debris(folder, name, since)
    stage = home / staging_name(name)
    with contextlib.nullcontext(tx) if tx is not None else outputs(label, out) as tx:
        with _locked():
            stage.mkdir()
            interrupt.CLEANUP.append(str(stage))
        tx.stages.append(stage)
        yield stage
        out.mkdir(parents=True, exist_ok=True)
        folders = sorted(out / p.relative_to(stage) for p in stage.rglob("*") if p.is_dir())
        for f in folders:  # all checked before anything is created or moved
            if f.exists() and not f.is_dir():
                raise NotADirectoryError(errno.ENOTDIR, "is not a directory (allowed a folder)", str(f))
        created = [f for f in folders if not os.path.lexists(f)]
        try:
            for f in folders:
                f.mkdir(parents=True, exist_ok=True)
            _move_in(tx, stage, out)
            tx.commit()  # in place when the block ends (the command reads them back)
        except BaseException:  # nothing moved in: the folders made for it go again (a new one stays empty)
            for f in sorted(created, key=lambda q: len(q.parts), reverse=True):
                with contextlib.suppress(OSError):
                    f.rmdir()
            raise
        with _locked():
            shutil.rmtree(stage, ignore_errors=True)
            _forget(stage)
            tx.stages.remove(stage)


def _move_in(tx: Outputs, stage: Path, out: Path) -> None:
    """Every file of the staging folder joins the set of outputs, to be renamed into ``out`` at the same
    relative path (the link rule of the module docstring)."""
    for f in sorted(p for p in stage.rglob("*") if not p.is_dir()):
        asked = out / f.relative_to(stage)
        target, atomic = resolve_target(asked)  # a link is followed, as by write_atomic
        if not atomic:  # a device or a pipe at the name: written in place, as write_atomic does
            shutil.copyfile(f, target)
            continue
        tx.pending.append((f, target))
        tx.asked[target] = asked
        interrupt.CLEANUP.append(str(f))


def read_manifest(folder: str | Path, command: str) -> dict | None:
    """The manifest ``<command>.manifest.json`` of a folder of outputs, or None where there is none;
    ``ValueError`` naming it when it says that its run was stopped while moving its files in
    (``"complete": false``) or when it cannot be read."""
    from .jsontext import read_json

    path = Path(folder) / MANIFEST.format(command)
    if not path.exists():
        return None
    try:
        doc = read_json(path)
    except (OSError, ValueError) as e:
        raise ValueError(f"{str(path)!r} cannot be read: {e}") from None
    if doc.get("complete") is not True:
        raise ValueError(
            f"{str(path)!r}: the run that wrote this folder was stopped while moving its files in "
            "(complete: false): its files mix two runs; run the command again"
        )
    return doc
