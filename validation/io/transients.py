"""The files of the Figs. 9-11 experiments (:mod:`gear_rattle.validation.transient.experiments`), written
into an output directory: ``basins.npz`` + ``basins.json`` (Fig. 9), ``uncertainty.npz`` +
``uncertainty.csv`` + ``uncertainty.json`` (Fig. 10), ``transients.npz`` + ``survival.csv`` +
``transients.json`` (Fig. 11), ``stick_time_sensitivity.json``.  Each writer returns the paths written."""

from __future__ import annotations

from pathlib import Path

from .formats import write_csv, write_json, write_npz


def out_dir(outdir) -> Path:
    """``outdir`` created (with its parents); ``ValueError`` naming it when that fails."""
    p = Path(outdir)
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise ValueError(f"outdir={str(outdir)!r} cannot be created: {e.strerror}") from None
    return p


def write_basins(outdir, res) -> list[Path]:
    """Fig. 9 (:class:`~gear_rattle.validation.transient.results.BasinsResult`)."""
    out = out_dir(outdir)
    return [write_npz(out / "basins.npz", **res.arrays()), write_json(out / "basins.json", res.summary())]


def write_uncertainty(outdir, res) -> list[Path]:
    """Fig. 10 (:class:`~gear_rattle.validation.transient.results.UncertaintyResult`)."""
    out = out_dir(outdir)
    return [
        write_npz(out / "uncertainty.npz", **res.arrays()),
        write_csv(out / "uncertainty.csv", *res.table()),
        write_json(out / "uncertainty.json", res.summary()),
    ]


def write_survival(outdir, res) -> list[Path]:
    """Fig. 11 (:class:`~gear_rattle.validation.transient.results.SurvivalResult`)."""
    out = out_dir(outdir)
    return [
        write_npz(out / "transients.npz", **res.arrays()),
        write_csv(out / "survival.csv", *res.survival_table()),
        write_json(out / "transients.json", res.summary()),
    ]


def write_stick_time_sensitivity(outdir, res) -> list[Path]:
    """The chatter-threshold sensitivity
    (:class:`~gear_rattle.validation.transient.results.StickTimeSensitivity`)."""
    return [write_json(out_dir(outdir) / "stick_time_sensitivity.json", res.summary())]


__all__ = [
    "out_dir",
    "write_basins",
    "write_uncertainty",
    "write_survival",
    "write_stick_time_sensitivity",
]
