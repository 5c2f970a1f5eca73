"""What makes an atlas store trustworthy on resume: a SHA-256 digest of every tile's every array, recorded
with the tile's ``done`` flag, and a digest of the store's attributes.

* **Tile digests.**  For tile ``(i, j)`` and each array ``name`` of the checked arrays (the fields and the
  timings), :func:`tile_digest` is SHA-256 over a header naming the array, the tile and the values'
  shape and dtype, then the values' bytes (C order, little-endian, the store's dtype).  The store keeps
  them in the ``checksum`` array (``uint8``, shape ``(tiles_r, tiles_alpha, n_arrays, 32)``, one chunk per
  tile), written after the tile's data and before its ``done`` flag.  :func:`verify` reads every tile
  marked done and recomputes them: a flipped bit, a deleted chunk (read back as fill values), a chunk
  copied from another tile (its values, or the tile named in the header, differ), a truncated chunk (it
  does not decompress) and a damaged ``done`` or ``checksum`` chunk each make the tile :class:`Damage`,
  named by tile and array chunk; the store then recomputes it.
* **Attribute digest.**  :func:`meta_digest` is SHA-256 over the canonical JSON of the attributes that
  define the atlas (:data:`META`), stored as the attribute ``sha256``: a changed spec value is damage,
  not "another spec".
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Attributes covered by the attribute digest.
META = ("format", "spec", "tile", "engine", "checked")

#: Bytes of one digest.
DIGEST_BYTES = 32


def tile_digest(name: str, i: int, j: int, values) -> np.ndarray:
    """SHA-256 (32 ``uint8``) of array ``name``'s values in tile ``(i, j)``: header, then the bytes."""
    v = np.ascontiguousarray(values)
    v = v.astype(v.dtype.newbyteorder("<"), copy=False)
    h = hashlib.sha256(f"gear-rattle-atlas tile {name} {i} {j} {v.shape} {v.dtype.str}\n".encode())
    h.update(v.tobytes())
    return np.frombuffer(h.digest(), dtype=np.uint8)


def meta_digest(attrs: dict) -> str:
    """SHA-256 (hex) of the canonical JSON of the attributes :data:`META`."""
    text = json.dumps({k: attrs.get(k) for k in META}, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


@dataclass
class Damage:
    """A tile marked done whose data cannot be trusted: ``tile`` ``(i, j)`` and what is wrong, per array."""

    tile: tuple[int, int]
    problems: list[str]

    def __str__(self) -> str:
        return f"tile {self.tile}: {'; '.join(self.problems)}"


def short_error(e: BaseException) -> str:
    """An exception's message on one line, at most 100 characters."""
    text = " ".join(str(e).split()) or type(e).__name__
    return text if len(text) <= 100 else text[:97] + "..."


class _Reader:
    """Reads one array of a store whole, or chunk by chunk where the whole read fails (a damaged chunk)."""

    def __init__(self, group, root: Path, name: str):
        self.arr = group[name]
        self.root, self.name = root, name
        self.bad: dict[tuple[int, int], str] = {}
        try:
            self.data: np.ndarray | None = np.asarray(self.arr[...])
        except Exception:  # noqa: BLE001 - a chunk that does not decode: find which, tile by tile
            self.data = None

    def key(self, i: int, j: int) -> str:
        """The chunk's key, ``lambda1/c/0/1``."""
        idx = (i, j) + (0,) * (self.arr.ndim - 2)
        return f"{self.name}/{self.arr.metadata.encode_chunk_key(idx)}"

    def exists(self, i: int, j: int) -> bool:
        return (self.root / self.key(i, j)).exists()

    def tile(self, i: int, j: int, sl: tuple[slice, ...]):
        """The values of tile ``(i, j)`` (``sl``: its index ranges), or None with the reason in ``bad``."""
        if self.data is not None:
            return self.data[sl]
        try:
            return np.asarray(self.arr[sl])
        except Exception as e:  # noqa: BLE001
            self.bad[(i, j)] = f"{self.key(i, j)} is unreadable ({short_error(e)})"
            return None


def verify(group, root: str, n_tiles: tuple[int, int], checked: tuple[str, ...], slices) -> list[Damage]:
    """The tiles of ``group`` marked done whose data or records are damaged (row-major order).

    ``root``: the store's directory (to tell a missing chunk file from a changed one); ``slices(name, i,
    j)``: tile ``(i, j)``'s index ranges in array ``name``.  Never raises for damaged chunks."""
    base = Path(root)
    done, sums = _Reader(group, base, "done"), _Reader(group, base, "checksum")
    arrays = {k: _Reader(group, base, k) for k in checked}
    out = []
    for i in range(n_tiles[0]):
        for j in range(n_tiles[1]):
            flag = done.tile(i, j, (slice(i, i + 1), slice(j, j + 1)))
            if flag is None:
                out.append(Damage((i, j), [f"its done flag {done.bad[(i, j)]}"]))
                continue
            if not bool(flag.ravel()[0]):
                continue
            problems = []
            rec = sums.tile(i, j, (slice(i, i + 1), slice(j, j + 1)))
            if rec is None:
                out.append(Damage((i, j), [f"its checksum {sums.bad[(i, j)]}"]))
                continue
            rec = rec.reshape(len(checked), -1)
            for n, (k, rd) in enumerate(arrays.items()):
                v = rd.tile(i, j, slices(k, i, j))
                if v is None:
                    problems.append(f"{k} chunk {rd.bad[(i, j)]}")
                elif not rec[n].any():
                    problems.append(f"{k} chunk {rd.key(i, j)} has no checksum recorded")
                elif not np.array_equal(tile_digest(k, i, j, v), rec[n]):
                    why = "is missing" if not rd.exists(i, j) else "does not match its checksum"
                    problems.append(f"{k} chunk {rd.key(i, j)} {why}")
            if problems:
                out.append(Damage((i, j), problems))
    return out


def forget(root: str, group, tile: tuple[int, int], names: tuple[str, ...]) -> None:
    """Delete tile ``tile``'s chunk files of ``names`` (a damaged tile is recomputed from nothing: a
    truncated chunk is never read again, not even to update part of it)."""
    for k in names:
        rd = group[k]
        idx = tile + (0,) * (rd.ndim - 2)
        (Path(root) / k / rd.metadata.encode_chunk_key(idx)).unlink(missing_ok=True)


__all__ = [
    "META",
    "DIGEST_BYTES",
    "tile_digest",
    "meta_digest",
    "Damage",
    "short_error",
    "verify",
    "forget",
]
