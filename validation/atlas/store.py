"""The atlas on disk: a Zarr (v3) group written tile by tile, so that an interrupted run loses nothing it
finished and a rerun computes only the missing tiles.

Layout of ``STORE/`` (arrays indexed ``[i_r, i_alpha]``; one Zarr chunk per tile):

=====================  ==========================  =================================================
name                   shape, chunks, dtype        content
=====================  ==========================  =================================================
``alpha``, ``r``       (n_alpha,), (n_r,) float64  the grid (:attr:`AtlasSpec.alphas`, ``.rs``)
``lambda1`` ...        (n_r, n_alpha), tile        the fields of :data:`.compute.FIELDS` (fill values
                                                   NaN / 0 / status -1 where not computed)
``done``               (tiles_r, tiles_alpha), 1   True once every field of that tile is written
``checksum``           (tiles_r, tiles_alpha,      SHA-256 of each array of :data:`CHECKED` in the tile
                       7, 32), one tile, uint8     (:mod:`.integrity`), written before ``done``
``tile_seconds``       (tiles_r, tiles_alpha), 1   wall time of the tile's compute on its worker
``tile_cpu_seconds``   (tiles_r, tiles_alpha), 1   CPU time of that worker process meanwhile (all
                                                   its threads; first tile of a worker: with compile)
=====================  ==========================  =================================================

Group attributes: ``format`` (:data:`FORMAT`), ``spec`` (:meth:`AtlasSpec.to_dict`), ``tile``
(``[tile_r, tile_alpha]``), ``engine`` (:data:`.compute.ENGINE`), ``checked`` (:data:`CHECKED`) and
``sha256`` (:func:`.integrity.meta_digest` of the others).  A tile's ``done`` flag is written after its
data and checksums, by the one process that writes (the client, holding the store's lock,
:mod:`..writelock`), so a tile is either done and verified on resume, or recomputed.
"""

from __future__ import annotations

import math
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np
import numpy.typing as npt

from ...core.checks import check_int
from .compute import ENGINE, FIELDS
from ..extras import require
from .integrity import DIGEST_BYTES, Damage, short_error, forget, meta_digest, tile_digest, verify
from .spec import AtlasSpec

if TYPE_CHECKING:  # zarr is the `atlas` extra, imported where a store is opened (import_zarr)
    import zarr

#: Per-tile timing arrays (float64, NaN until the tile is done).
TIMING = ("tile_seconds", "tile_cpu_seconds")

#: Format tag of the store's attributes (2: with checksums).
FORMAT = "gear-rattle-atlas/2"

#: Formats of older versions: recognised as atlas stores (``--overwrite`` replaces them), never resumed.
OLD_FORMATS = ("gear-rattle-atlas/1",)

#: The per-tile arrays whose digests are recorded (in this order) in the ``checksum`` array.
CHECKED = (*FIELDS, *TIMING)


class StoreWriteError(RuntimeError):
    """The store cannot be written (disk full, permissions, ...): one line naming the store."""


def import_zarr():
    """The ``zarr`` module, or :class:`~validation.extras.MissingExtra` naming the ``atlas`` extra."""
    return require("zarr", "atlas", "the atlas")


def check_tile(tile) -> tuple[int, int]:
    """``(tile_r, tile_alpha)`` from an int or a pair of ints, each ``1 <= n <= 1000000``
    (:func:`core.checks.check_int`: ``ValueError``/``TypeError`` naming ``tile``, ``tile_r`` or ``tile_alpha``)."""
    if isinstance(tile, (tuple, list)):
        if len(tile) != 2:
            raise ValueError(f"tile={tile!r} is out of range: allowed an integer >= 1 or a pair of them")
        return check_int("tile_r", tile[0], 1, 1_000_000, strict=True), check_int(
            "tile_alpha", tile[1], 1, 1_000_000, strict=True
        )
    t = check_int("tile", tile, 1, 1_000_000, strict=True)
    return t, t


#: Most grid points per tile: every tile is one task padded to the full tile shape (see :mod:`.run`), so
#: its memory grows with the tile's area (1024 x 1024 tiles: ~1 GB per worker).
MAX_TILE_POINTS = 1 << 20


def fit_tile(spec: AtlasSpec, tile) -> tuple[int, int]:
    """The tile shape an atlas of ``spec`` uses for the requested ``tile`` (:func:`check_tile`): each side
    clamped to the grid (a tile larger than the grid computed its padding: ``--tile 256`` on a 2 x 2 grid
    ran 65536 orbits for 4 points), then at most :data:`MAX_TILE_POINTS` points (``ValueError`` naming
    ``tile`` otherwise; ``--tile 100000`` allocated 74.5 GiB)."""
    tr, ta = check_tile(tile)
    fit = (min(tr, spec.n_r), min(ta, spec.n_alpha))
    if fit[0] * fit[1] > MAX_TILE_POINTS:
        raise ValueError(
            f"tile={tile!r} is out of range on a {spec.n_r} x {spec.n_alpha} grid: a tile of {fit[0]} x "
            f"{fit[1]} points, allowed at most {MAX_TILE_POINTS} points per tile (e.g. tile <= 1024)"
        )
    return fit


def tile_grid(spec: AtlasSpec, tile: tuple[int, int]) -> tuple[int, int]:
    """Number of tiles along r and along alpha."""
    return math.ceil(spec.n_r / tile[0]), math.ceil(spec.n_alpha / tile[1])


def tile_slices(spec: AtlasSpec, tile: tuple[int, int], i: int, j: int) -> tuple[slice, slice]:
    """Index ranges ``(rows, cols)`` of tile ``(i, j)`` in the atlas arrays (edge tiles are smaller)."""
    return (
        slice(i * tile[0], min((i + 1) * tile[0], spec.n_r)),
        slice(j * tile[1], min((j + 1) * tile[1], spec.n_alpha)),
    )


def _diff(a: dict, b: dict) -> str:
    keys = sorted(set(a) | set(b))
    return ", ".join(f"{k} {a.get(k)!r} (store) != {b.get(k)!r}" for k in keys if a.get(k) != b.get(k))


def _mismatch(key: str, have: object, want: object) -> str:
    """One attribute of a store that differs from the one being opened: a dict's differing entries
    (:func:`_diff`), else both values."""
    if isinstance(have, dict) and isinstance(want, dict):
        return f"{key}: {_diff(have, want)}"
    return f"{key} {have!r} (store) != {want!r}"


@dataclass
class AtlasStore:
    """An open atlas store (create with :func:`open_store`)."""

    path: str
    spec: AtlasSpec
    tile: tuple[int, int]
    group: zarr.Group
    #: Tiles found done but damaged when the store was opened (forgotten: they are computed again).
    damaged: list[Damage] = field(default_factory=list)

    @property
    def n_tiles(self) -> tuple[int, int]:
        return tile_grid(self.spec, self.tile)

    def done(self) -> np.ndarray:
        """Boolean ``(tiles_r, tiles_alpha)``: which tiles are stored."""
        return np.asarray(self._array("done")[...], dtype=bool)

    def missing(self) -> list[tuple[int, int]]:
        """Tiles not yet stored, in row-major order."""
        return [(int(i), int(j)) for i, j in zip(*np.nonzero(~self.done()))]

    def write_tile(
        self,
        i: int,
        j: int,
        result: dict[str, np.ndarray],
        seconds: float = float("nan"),
        cpu_seconds: float = float("nan"),
    ) -> None:
        """Store the fields of tile ``(i, j)`` (arrays of the tile's shape) and its timing, then their
        checksums, then mark it done (its old chunks, if any, are deleted first, ``done`` first of all)."""
        rows, cols = tile_slices(self.spec, self.tile, i, j)
        shape = (rows.stop - rows.start, cols.stop - cols.start)
        for k, (dt, _) in FIELDS.items():
            v = np.asarray(result[k])
            if v.shape != shape or v.dtype != dt:
                raise ValueError(
                    f"tile ({i}, {j}) field {k!r} has shape {v.shape} and dtype {v.dtype}: allowed {shape} and {dt}"
                )
        values = {
            **{k: np.asarray(result[k]) for k in FIELDS},
            "tile_seconds": np.full((1, 1), float(seconds)),
            "tile_cpu_seconds": np.full((1, 1), float(cpu_seconds)),
        }
        try:
            forget(self.path, self.group, (i, j), ("done", "checksum", *CHECKED))  # written from nothing
            for k, v in values.items():
                self._array(k)[self._slices(k, i, j)] = v
            self._array("checksum")[i, j] = np.stack([tile_digest(k, i, j, values[k]) for k in CHECKED])
            self._array("done")[i, j] = True
        except OSError as e:
            raise StoreWriteError(f"store {self.path!r}: cannot write tile ({i}, {j}): {e.strerror or e}") from None

    def _array(self, name: str) -> zarr.Array:
        """The store's array ``name`` (zarr types a group's item as an array or a group: every name used
        here is one of the store's arrays)."""
        return cast("zarr.Array", self.group[name])

    def _slices(self, name: str, i: int, j: int) -> tuple[slice, slice]:
        """Tile ``(i, j)``'s index ranges in array ``name`` (a field or a per-tile array)."""
        return tile_slices(self.spec, self.tile, i, j) if name in FIELDS else (slice(i, i + 1), slice(j, j + 1))

    def verify(self) -> list[Damage]:
        """The tiles marked done whose data, checksums or done flag are damaged (:func:`.integrity.verify`)."""
        return verify(self.group, self.path, self.n_tiles, CHECKED, self._slices)

    def read(self) -> dict[str, np.ndarray]:
        """Every array of the store (``alpha``, ``r``, the fields, ``done`` and the timings)."""
        return {k: np.asarray(self._array(k)[...]) for k in ("alpha", "r", *FIELDS, "done", *TIMING)}


def _known_format(attrs: dict) -> bool:
    return attrs.get("format") == FORMAT or attrs.get("format") in OLD_FORMATS


def _looks_like_atlas(p: Path) -> bool:
    """A folder with the atlas's Zarr layout (its metadata may be damaged)."""
    return p.is_dir() and (p / "zarr.json").exists() and any((p / k).is_dir() for k in ("done", *FIELDS))


def _read_attrs(p: Path, zarr) -> tuple[dict | None, str]:
    """The group attributes of the store at ``p``, or ``(None, why not)``."""
    try:
        g = zarr.open_group(str(p), mode="r")
        return dict(g.attrs), ""
    except Exception as e:  # noqa: BLE001 - anything unreadable is described, not raised
        return None, f"{p / 'zarr.json'} is unreadable ({short_error(e)})"


def _damaged(p: Path, why: str) -> ValueError:
    return ValueError(
        f"store {str(p)!r} is damaged: {why}; it was left as it is (delete it or move it away to start again)"
    )


def _check_meta(p: Path, zarr, attrs: dict, want: dict | None) -> None:
    """``ValueError`` (:func:`_damaged`) unless the attributes match their digest and every array's
    metadata has the shape, chunks and dtype of the store's spec and tile (``want``: the attributes of the
    store being opened, None: those of the store itself)."""
    if attrs.get("creating"):
        return
    if attrs.get("sha256") != meta_digest(attrs):
        raise _damaged(p, f"its attributes ({p / 'zarr.json'}) do not match their checksum")
    try:
        spec, tile = AtlasSpec.from_dict(attrs["spec"]), tuple(attrs["tile"])
    except (KeyError, TypeError, ValueError) as e:
        raise _damaged(p, f"its spec in {p / 'zarr.json'} is invalid ({short_error(e)})") from None
    if want is not None and (spec.to_dict() != want["spec"] or list(tile) != want["tile"]):
        return  # another atlas: refused (or overwritten) by the caller, its arrays do not matter
    nt = tile_grid(spec, tile)
    layout: dict[str, tuple[tuple[int, ...], npt.DTypeLike]] = {
        "alpha": ((spec.n_alpha,), np.float64),
        "r": ((spec.n_r,), np.float64),
        **{k: (spec.shape, dt) for k, (dt, _) in FIELDS.items()},
        **{k: (nt, np.float64) for k in TIMING},
        "done": (nt, np.bool_),
        "checksum": ((*nt, len(CHECKED), DIGEST_BYTES), np.uint8),
    }
    g = zarr.open_group(str(p), mode="r")
    for k, (shape, dt) in layout.items():
        try:
            a = g[k]
            ok = a.shape == shape and a.dtype == dt
        except Exception as e:  # noqa: BLE001
            raise _damaged(p, f"array {k!r} ({p / k / 'zarr.json'}) is unreadable ({short_error(e)})") from None
        if not ok:
            raise _damaged(
                p,
                f"array {k!r} ({p / k / 'zarr.json'}) has shape {a.shape} and dtype {a.dtype}, "
                f"its spec says {shape} and {np.dtype(dt)}",
            )
    try:
        grid_ok = np.array_equal(g["alpha"][...], spec.alphas) and np.array_equal(g["r"][...], spec.rs)
    except Exception as e:  # noqa: BLE001
        raise _damaged(p, f"its grid (alpha, r) is unreadable ({short_error(e)})") from None
    if not grid_ok:
        raise _damaged(p, "its grid (alpha, r) differs from its spec")


def _remove(p: Path) -> None:
    try:
        shutil.rmtree(p)
    except OSError as e:
        raise StoreWriteError(f"store {str(p)!r} cannot be replaced: {e.strerror or e}") from None


def open_store(path: str, spec: AtlasSpec, tile=(16, 16), overwrite: bool = False) -> AtlasStore:
    """Open the atlas store at ``path`` for ``spec`` and ``tile``, creating it if absent.

    The caller holds the store's lock (:class:`..writelock.StoreLock`; :func:`.run.run_atlas` does).
    ``tile`` is fitted to the grid (:func:`fit_tile`).  An existing store made with another spec, tile
    size, engine or format is refused (``ValueError``, one line) unless ``overwrite``, which deletes and
    recreates it.  An existing store is checked first (:mod:`.integrity`): damaged metadata (attributes,
    an array's metadata, the grid) is refused in one line naming it, even with ``overwrite``, and nothing is
    deleted; a tile marked done whose data do not match their checksums is forgotten (its chunks
    deleted, recomputed by the run), listed in ``AtlasStore.damaged``.  A path that exists but is not
    an atlas store (a file, a non-empty folder of something else) is always refused.
    """
    zarr = import_zarr()
    tile = fit_tile(spec, tile)
    p = Path(path)
    want = {"format": FORMAT, "spec": spec.to_dict(), "tile": list(tile), "engine": ENGINE, "checked": list(CHECKED)}
    if p.exists():
        attrs, why = _read_attrs(p, zarr) if p.is_dir() else (None, "")
        if attrs is None or not _known_format(attrs):
            if _looks_like_atlas(p):
                raise _damaged(
                    p,
                    why
                    or f"its attributes ({p / 'zarr.json'}) are not an atlas's "
                    f"({', '.join(sorted(attrs or {})) or 'empty'})",
                )
            if p.is_file() or any(p.iterdir()):
                raise ValueError(
                    f"store {str(p)!r} exists and is not an atlas store: allowed a new path or an existing atlas store"
                )
        elif attrs.get("creating"):  # its creation was interrupted (under the lock): start again
            _remove(p)
        else:
            if attrs.get("format") == FORMAT:
                _check_meta(p, zarr, attrs, want)
            if overwrite:
                _remove(p)
            else:
                have = {k: attrs.get(k) for k in want}
                if have["format"] != FORMAT:
                    raise ValueError(
                        f"store {str(p)!r} has the format {have['format']!r} of an older version, "
                        f"without checksums (now {FORMAT!r}): overwrite it (overwrite=True, "
                        "--overwrite) to recompute it"
                    )
                if have != want:
                    parts = [_mismatch(k, have[k], want[k]) for k in want if have[k] != want[k]]
                    raise ValueError(
                        f"store {str(p)!r} holds an atlas with a different spec ({'; '.join(parts)}): "
                        "rerun with the store's options, or overwrite it (overwrite=True, --overwrite)"
                    )
                g = zarr.open_group(str(p), mode="r+")
                st = AtlasStore(str(p), spec, tile, g)
                st.damaged = st.verify()
                try:
                    for d in st.damaged:
                        forget(st.path, g, d.tile, ("done", "checksum", *CHECKED))
                except OSError as e:
                    raise StoreWriteError(
                        f"store {str(p)!r}: cannot delete a damaged tile's chunks: {e.strerror or e}"
                    ) from None
                return st
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        # the attributes come first, marked as being created: a store without them is damaged, not half made
        g = zarr.open_group(str(p), mode="w", attributes={"format": FORMAT, "creating": True})
        shape, nt = spec.shape, tile_grid(spec, tile)
        g.create_array("alpha", data=spec.alphas, chunks=(spec.n_alpha,))
        g.create_array("r", data=spec.rs, chunks=(spec.n_r,))
        for k, (dt, fill) in FIELDS.items():
            g.create_array(k, shape=shape, chunks=tile, dtype=dt, fill_value=fill)
        for k in TIMING:
            g.create_array(k, shape=nt, chunks=(1, 1), dtype=np.float64, fill_value=np.nan)
        g.create_array("done", shape=nt, chunks=(1, 1), dtype=bool, fill_value=False)
        g.create_array(
            "checksum",
            shape=(*nt, len(CHECKED), DIGEST_BYTES),
            chunks=(1, 1, len(CHECKED), DIGEST_BYTES),
            dtype=np.uint8,
            fill_value=0,
        )
        g.attrs.put({**want, "sha256": meta_digest(want)})  # last: the store is made
    except OSError as e:
        raise StoreWriteError(f"store {str(p)!r} cannot be created: {e.strerror or e}") from None
    return AtlasStore(str(p), spec, tile, g)


def load_store(path: str) -> AtlasStore:
    """Open an existing atlas store read-only, with the spec and tile size it was made with."""
    zarr = import_zarr()
    p = Path(path)
    attrs, why = _read_attrs(p, zarr)
    if attrs is None or attrs.get("format") != FORMAT or attrs.get("creating"):
        if _looks_like_atlas(p):
            raise _damaged(p, why or f"its attributes ({p / 'zarr.json'}) are not those of a finished atlas store")
        raise ValueError(f"store {path!r} is not an atlas store")
    _check_meta(p, zarr, attrs, None)
    g = zarr.open_group(str(path), mode="r")
    return AtlasStore(str(path), AtlasSpec.from_dict(attrs["spec"]), tuple(attrs["tile"]), g)


__all__ = [
    "TIMING",
    "FORMAT",
    "OLD_FORMATS",
    "CHECKED",
    "StoreWriteError",
    "import_zarr",
    "check_tile",
    "MAX_TILE_POINTS",
    "fit_tile",
    "tile_grid",
    "tile_slices",
    "AtlasStore",
    "open_store",
    "load_store",
]
