"""The summary of an atlas (a typed :class:`AtlasSummary`): what was run, how fast, and what the plane
holds (counts, period classes, and the atlas along the paper's scans)."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from ..paper import PAPER_SCANS
from .run import AtlasRun
from .spec import PAPER_LINES, AtlasSpec


#: Most (p, m) classes coloured individually in the period panel; the rest are "other periodic".
MAX_CLASSES = 12


def period_classes(p: np.ndarray, m: np.ndarray, max_classes: int = MAX_CLASSES) -> list[tuple[int, int, int]]:
    """``(p, m, count)`` of the periodic points, most frequent first (ties: smaller p, then m)."""
    c = Counter(zip(p[p > 0].tolist(), m[p > 0].tolist()))
    return [(pp, mm, n) for (pp, mm), n in sorted(c.items(), key=lambda t: (-t[1], t[0]))][:max_classes]


def paper_plane(spec: AtlasSpec) -> bool:
    """Whether the atlas's plane is the one of the paper's scans (their beta and gamma,
    :data:`validation.paper.PAPER_SCANS`): only there are the paper's scans drawn and profiled."""
    return all((spec.beta, spec.gamma) == (s.fixed[1], s.fixed[2]) for s in PAPER_SCANS.values())


def no_paper_lines(spec: AtlasSpec) -> str:
    """The line ``atlas_summary.json`` carries instead of the profiles along the paper's scans where the
    plane is not the paper's."""
    planes = sorted({(s.fixed[1], s.fixed[2]) for s in PAPER_SCANS.values()})
    theirs = " or ".join(f"beta={b!r}, gamma={g!r}" for b, g in planes)
    return (
        f"no comparison with the paper: the plane (beta={spec.beta!r}, gamma={spec.gamma!r}) is not the one of "
        f"the paper's scans ({theirs})"
    )


def paper_lines(spec: AtlasSpec):
    """The paper's scans clipped to the atlas: ``(label, (x0, x1), (y0, y1))`` in (alpha, r) coordinates,
    only those that cross the atlas, and none where the plane is not the paper's (:func:`paper_plane`)."""
    out: list = []
    if not paper_plane(spec):
        return out
    for label, fixed, value, _varied, lo, hi in PAPER_LINES:
        if fixed == "alpha":
            if not spec.alpha_lo <= value <= spec.alpha_hi:
                continue
            y0, y1 = max(lo, spec.r_lo), min(hi, spec.r_hi)
            if y0 <= y1:
                out.append((label, (value, value), (y0, y1)))
        else:
            if not spec.r_lo <= value <= spec.r_hi:
                continue
            x0, x1 = max(lo, spec.alpha_lo), min(hi, spec.alpha_hi)
            if x0 <= x1:
                out.append((label, (x0, x1), (value, value)))
    return out


def _line_profile(data: dict, spec: AtlasSpec, fixed: str, value: float, lo: float, hi: float) -> dict:
    """The atlas on the grid line nearest to the paper's scan (``fixed = value``, the other in [lo, hi])."""
    if fixed == "alpha":
        k = int(np.argmin(np.abs(data["alpha"] - value)))
        at, var = float(data["alpha"][k]), data["r"]
        sel = (var >= lo - 1e-12) & (var <= hi + 1e-12)
        lam, p, m = data["lambda1"][sel, k], data["period_p"][sel, k], data["period_m"][sel, k]
    else:
        k = int(np.argmin(np.abs(data["r"] - value)))
        at, var = float(data["r"][k]), data["alpha"]
        sel = (var >= lo - 1e-12) & (var <= hi + 1e-12)
        lam, p, m = data["lambda1"][k, sel], data["period_p"][k, sel], data["period_m"][k, sel]
    return {
        "grid_line": {fixed: at},
        "points": int(sel.sum()),
        "chaotic (lambda1 > 0)": int(np.sum(np.isfinite(lam) & (lam > 0))),
        "periodic": int(np.sum(p > 0)),
        "periods": [{"p": a, "m": b, "count": n} for a, b, n in period_classes(p, m)],
        "values": [
            {"x": float(x), "lambda1": (None if np.isnan(l) else float(l)), "p": int(pp), "m": int(mm)}
            for x, l, pp, mm in zip(var[sel], lam, p, m)
        ],
    }


@dataclass
class AtlasSummary:
    """What an atlas holds and how it was computed: ``points`` of the grid and ``points_computed``,
    ``tiles_done`` of ``tiles_total``; counts over the computed points: ``chaotic`` (lambda1 > 0),
    ``periodic`` (a period found), ``sticking`` (lambda1 = -inf), ``ended`` (status != 0),
    ``periodic_chaotic`` (a period found but lambda1 > 0: a chaotic transient that ended during the
    measurement); ``period_classes``: the most frequent ``(p, m, count)``; ``paper_lines``: the atlas
    along the paper's scans (per label, ``_line_profile``; none, and in the JSON the line of
    :func:`no_paper_lines`, where the plane is not the paper's); ``run``: timing and throughput of the run
    (None without one); ``store``: where the atlas is (set by the caller).  :meth:`as_dict` is the
    content of ``atlas_summary.json``."""

    spec: AtlasSpec
    points: int
    points_computed: int
    tiles_done: int
    tiles_total: int
    chaotic: int
    periodic: int
    sticking: int
    ended: int
    periodic_chaotic: int
    period_classes: list
    paper_lines: dict
    run: dict | None = None
    store: str | None = None

    def as_dict(self) -> dict:
        out = {
            "spec": self.spec.to_dict(),
            "points": self.points,
            "points_computed": self.points_computed,
            "tiles_done": self.tiles_done,
            "tiles_total": self.tiles_total,
            "chaotic (lambda1 > 0)": self.chaotic,
            "periodic (period found)": self.periodic,
            "sticking (lambda1 = -inf)": self.sticking,
            "ended (status != 0)": self.ended,
            "period found but lambda1 > 0 (transient ended during the measurement)": self.periodic_chaotic,
            "period classes": [{"p": a, "m": b, "count": n} for a, b, n in self.period_classes],
            "paper lines": self.paper_lines if paper_plane(self.spec) else no_paper_lines(self.spec),
        }
        if self.run is not None:
            out["run"] = self.run
        if self.store is not None:
            out["store"] = self.store
        return out


def _run_record(data: dict[str, np.ndarray], spec: AtlasSpec, run: AtlasRun) -> dict:
    out = {
        "scheduler": run.scheduler,
        "workers": run.workers,
        "tile": list(run.store.tile),
        "tiles_computed": len(run.computed),
        "tiles_resumed": run.skipped,
        "tiles_damaged": [list(d.tile) for d in run.store.damaged],
        "points_computed": run.points_computed,
        "impacts_per_point": spec.impacts_per_point,
        "wall_seconds": run.seconds,
        "throughput (points x impacts / s, wall, start-up and compile included)": run.throughput,
    }
    out.update(tile_throughput(data, spec, run))
    return out


def summarise(data: dict[str, np.ndarray], spec: AtlasSpec, run: AtlasRun | None = None) -> AtlasSummary:
    """Counts over the computed points, the ten most frequent period classes, the profiles along the
    paper's scans, and (given ``run``) timing and throughput (grid points x map steps per second)."""
    done_pts = data["status"] >= 0
    lam = data["lambda1"]
    chaotic = done_pts & np.isfinite(lam) & (lam > 0)
    periodic = done_pts & (data["period_p"] > 0)
    shown = {lab for lab, _, _ in paper_lines(spec)}
    return AtlasSummary(
        spec,
        int(done_pts.size),
        int(done_pts.sum()),
        int(data["done"].sum()),
        int(data["done"].size),
        chaotic=int(np.sum(chaotic)),
        periodic=int(np.sum(periodic)),
        sticking=int(np.sum(done_pts & np.isneginf(lam))),
        ended=int(np.sum(done_pts & (data["status"] > 0))),
        periodic_chaotic=int(np.sum(periodic & chaotic)),
        period_classes=period_classes(data["period_p"], data["period_m"], 10),
        paper_lines={
            lab: _line_profile(data, spec, fixed, value, lo, hi)
            for lab, fixed, value, _v, lo, hi in PAPER_LINES
            if lab in shown
        },
        run=_run_record(data, spec, run) if run is not None else None,
    )


def tile_throughput(data: dict[str, np.ndarray], spec: AtlasSpec, run: AtlasRun) -> dict:
    """Median over the tiles computed by ``run`` of (tile points x impacts per point) / (tile wall time) and
    / (tile CPU time): the steady rate of one worker (the median skips each worker's first tile, which
    includes tracing and compiling the kernel, when there are enough tiles)."""
    if not run.computed:
        return {}
    from .store import tile_slices

    pts_l, wall_l, cpu_l = [], [], []
    for i, j in run.computed:
        rows, cols = tile_slices(spec, run.store.tile, i, j)
        pts_l.append((rows.stop - rows.start) * (cols.stop - cols.start) * spec.impacts_per_point)
        wall_l.append(data["tile_seconds"][i, j])
        cpu_l.append(data["tile_cpu_seconds"][i, j])
    pts, wall, cpu = (np.asarray(x, dtype=float) for x in (pts_l, wall_l, cpu_l))
    return {
        "tile_seconds_sum": float(wall.sum()),
        "tile_cpu_seconds_sum": float(cpu.sum()),
        "median tile throughput per worker (points x impacts / s, wall)": float(np.median(pts / wall)),
        "median tile throughput per worker (points x impacts / CPU s)": float(np.median(pts / cpu)),
    }


__all__ = [
    "MAX_CLASSES",
    "period_classes",
    "paper_plane",
    "no_paper_lines",
    "paper_lines",
    "AtlasSummary",
    "summarise",
    "tile_throughput",
]
