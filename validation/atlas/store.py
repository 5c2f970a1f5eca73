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
``tile_seconds``       (tiles_r, tiles_alpha), 1   wall time of the tile's compute on its worker
``tile_cpu_seconds``   (tiles_r, tiles_alpha), 1   CPU time of that worker process meanwhile (all
                                                   its threads; first tile of a worker: with compile)
=====================  ==========================  =================================================

Group attributes: ``format`` (:data:`FORMAT`), ``spec`` (:meth:`AtlasSpec.to_dict`), ``tile``
(``[tile_r, tile_alpha]``) and ``engine`` (:data:`.compute.ENGINE`).  A tile's ``done`` flag is written
after its data, by the one process that writes (the client), so a tile is either done or recomputed.
"""

from __future__ import annotations

import math
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...core.checks import check_int
from .compute import ENGINE, FIELDS
from ..extras import require
from .spec import AtlasSpec

#: Per-tile timing arrays (float64, NaN until the tile is done).
TIMING = ("tile_seconds", "tile_cpu_seconds")

#: Format tag of the store's attributes.
FORMAT = "gear-rattle-atlas/1"


def import_zarr():
    """The ``zarr`` module, or :class:`~validation.extras.MissingExtra` naming the ``atlas`` extra."""
    return require("zarr", "atlas", "the atlas")


def check_tile(tile) -> tuple[int, int]:
    """``(tile_r, tile_alpha)`` from an int or a pair of ints, each ``1 <= n <= 1000000``
    (:func:`core.checks.check_int`: ``ValueError``/``TypeError`` naming ``tile``, ``tile_r`` or ``tile_alpha``)."""
    if isinstance(tile, (tuple, list)):
        if len(tile) != 2:
            raise ValueError(f"tile={tile!r} is out of range: allowed an integer >= 1 or a pair of them")
        return check_int("tile_r", tile[0], 1, 1_000_000, strict=True), check_int("tile_alpha", tile[1], 1, 1_000_000,
                                                                                  strict=True)
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
        raise ValueError(f"tile={tile!r} is out of range on a {spec.n_r} x {spec.n_alpha} grid: a tile of {fit[0]} x "
                         f"{fit[1]} points, allowed at most {MAX_TILE_POINTS} points per tile (e.g. tile <= 1024)")
    return fit


def tile_grid(spec: AtlasSpec, tile: tuple[int, int]) -> tuple[int, int]:
    """Number of tiles along r and along alpha."""
    return math.ceil(spec.n_r / tile[0]), math.ceil(spec.n_alpha / tile[1])


def tile_slices(spec: AtlasSpec, tile: tuple[int, int], i: int, j: int) -> tuple[slice, slice]:
    """Index ranges ``(rows, cols)`` of tile ``(i, j)`` in the atlas arrays (edge tiles are smaller)."""
    return (slice(i * tile[0], min((i + 1) * tile[0], spec.n_r)),
            slice(j * tile[1], min((j + 1) * tile[1], spec.n_alpha)))


def _diff(a: dict, b: dict) -> str:
    keys = sorted(set(a) | set(b))
    return ", ".join(f"{k} {a.get(k)!r} (store) != {b.get(k)!r}" for k in keys if a.get(k) != b.get(k))


@dataclass
class AtlasStore:
    """An open atlas store (create with :func:`open_store`)."""

    path: str
    spec: AtlasSpec
    tile: tuple[int, int]
    group: object

    @property
    def n_tiles(self) -> tuple[int, int]:
        return tile_grid(self.spec, self.tile)

    def done(self) -> np.ndarray:
        """Boolean ``(tiles_r, tiles_alpha)``: which tiles are stored."""
        return np.asarray(self.group["done"][...], dtype=bool)

    def missing(self) -> list[tuple[int, int]]:
        """Tiles not yet stored, in row-major order."""
        return [(int(i), int(j)) for i, j in zip(*np.nonzero(~self.done()))]

    def write_tile(self, i: int, j: int, result: dict[str, np.ndarray], seconds: float = float("nan"),
                   cpu_seconds: float = float("nan")) -> None:
        """Store the fields of tile ``(i, j)`` (arrays of the tile's shape) and its timing, then mark it done."""
        rows, cols = tile_slices(self.spec, self.tile, i, j)
        shape = (rows.stop - rows.start, cols.stop - cols.start)
        for k, (dt, _) in FIELDS.items():
            v = np.asarray(result[k])
            if v.shape != shape or v.dtype != dt:
                raise ValueError(f"tile ({i}, {j}) field {k!r} has shape {v.shape} and dtype {v.dtype}: "
                                 f"allowed {shape} and {dt}")
        for k in FIELDS:
            self.group[k][rows, cols] = np.asarray(result[k])
        self.group["tile_seconds"][i, j] = float(seconds)
        self.group["tile_cpu_seconds"][i, j] = float(cpu_seconds)
        self.group["done"][i, j] = True

    def read(self) -> dict[str, np.ndarray]:
        """Every array of the store (``alpha``, ``r``, the fields, ``done`` and the timings)."""
        return {k: np.asarray(self.group[k][...]) for k in ("alpha", "r", *FIELDS, "done", *TIMING)}


def _is_atlas(path: Path, zarr) -> dict | None:
    try:
        g = zarr.open_group(str(path), mode="r")
        attrs = dict(g.attrs)
    except Exception:  # noqa: BLE001 - anything unreadable is "not an atlas"
        return None
    return attrs if attrs.get("format") == FORMAT else None


def _half_made(path: Path, zarr) -> bool:
    try:
        g = zarr.open_group(str(path), mode="r")
        return not dict(g.attrs) and set(g.keys()) <= {"alpha", "r", "done", *TIMING, *FIELDS}
    except Exception:  # noqa: BLE001
        return False


def _tile_fits(stored, spec: AtlasSpec, tile: tuple[int, int]) -> bool:
    """Whether a store's tile (larger than the grid: made before :func:`fit_tile`) fits to ``tile``."""
    try:
        return tuple(stored) != tile and (min(stored[0], spec.n_r), min(stored[1], spec.n_alpha)) == tile
    except (TypeError, IndexError):
        return False


def open_store(path: str, spec: AtlasSpec, tile=(16, 16), overwrite: bool = False) -> AtlasStore:
    """Open the atlas store at ``path`` for ``spec`` and ``tile``, creating it if absent.

    ``tile`` is fitted to the grid (:func:`fit_tile`).  An existing store made with another spec, tile
    size or engine is refused (``ValueError``, one line) unless ``overwrite``, which deletes and
    recreates it.  A path that exists but is not an atlas store
    (a file, a non-empty folder of something else) is always refused.
    """
    zarr = import_zarr()
    tile = fit_tile(spec, tile)
    p = Path(path)
    want = {"format": FORMAT, "spec": spec.to_dict(), "tile": list(tile), "engine": ENGINE}
    if p.exists():
        attrs = _is_atlas(p, zarr)
        if attrs is None:
            if _half_made(p, zarr):  # creation was interrupted before the attributes: start again
                shutil.rmtree(p)
            elif p.is_file() or any(p.iterdir()):
                raise ValueError(f"store {str(p)!r} exists and is not an atlas store: allowed a new path or an "
                                 "existing atlas store")
        elif overwrite:
            shutil.rmtree(p)
        else:
            have = {k: attrs.get(k) for k in want}
            if _tile_fits(attrs.get("tile"), spec, tile):  # a store made before tiles were fitted to the grid
                want["tile"] = have["tile"]
                tile = tuple(have["tile"])
            if have != want:
                parts = [f"{k}: {_diff(have[k], want[k])}" if isinstance(want[k], dict) else
                         f"{k} {have[k]!r} (store) != {want[k]!r}" for k in want if have[k] != want[k]]
                raise ValueError(f"store {str(p)!r} holds an atlas with a different spec ({'; '.join(parts)}): "
                                 "rerun with the store's options, or overwrite it (overwrite=True, --overwrite)")
            g = zarr.open_group(str(p), mode="r+")
            return AtlasStore(str(p), spec, tile, g)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        g = zarr.open_group(str(p), mode="w")
    except OSError as e:
        raise ValueError(f"store {str(p)!r} cannot be created: {e.strerror or e}") from None
    shape, nt = spec.shape, tile_grid(spec, tile)
    g.create_array("alpha", data=spec.alphas, chunks=(spec.n_alpha,))
    g.create_array("r", data=spec.rs, chunks=(spec.n_r,))
    for k, (dt, fill) in FIELDS.items():
        g.create_array(k, shape=shape, chunks=tile, dtype=dt, fill_value=fill)
    for k in TIMING:
        g.create_array(k, shape=nt, chunks=(1, 1), dtype=np.float64, fill_value=np.nan)
    g.create_array("done", shape=nt, chunks=(1, 1), dtype=bool, fill_value=False)
    g.attrs.update(want)  # last: a store without its attributes is not an atlas (and is recreated)
    return AtlasStore(str(p), spec, tile, g)


def load_store(path: str) -> AtlasStore:
    """Open an existing atlas store read-only, with the spec and tile size it was made with."""
    zarr = import_zarr()
    attrs = _is_atlas(Path(path), zarr)
    if attrs is None:
        raise ValueError(f"store {path!r} is not an atlas store")
    g = zarr.open_group(str(path), mode="r")
    return AtlasStore(str(path), AtlasSpec.from_dict(attrs["spec"]), tuple(attrs["tile"]), g)
