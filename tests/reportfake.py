"""A small fake validation report for the report tests (tests/test_report.py, tests/test_report_page.py).

The real sections take minutes; :func:`fake_section` stands in for them: one section with every kind
of row the real report has (values that agree and disagree, bounds satisfied and violated, one
decided by an enclosure, a count, a category, internal checks, a row not in the paper, a value not
computed), texts as long as the real ones, a wide table and a wide figure (a real PNG).
"""

from __future__ import annotations

import struct
import types
import zlib
from pathlib import Path

from gear_rattle.validation.report import builder
from gear_rattle.validation.report.document import Section
from gear_rattle.validation.report.verdict import row

LONG = (
    "reported: the GOY law T ~ (alpha - alpha1)^(-g) fitted by maximum likelihood to the escape times from "
    "the chaotic set (400 orbits per alpha in the scans, 2000 in the bracket runs, settled on the attractor "
    "at alpha = 1.2) at 9 values of alpha, mean lifetimes up to 3.1e+05 impacts (g = 0.5012 of the saddle "
    "4-impact orbit): 1.243206 +- 2.8e-06, error: statistical 1.1e-06 and fit-range systematic 2.6e-06; "
    "exponent free: 1.243190 +- 9.0e-06; bracket by direct observation [1.243180, 1.243230]. "
) * 2


def png(width: int, height: int) -> bytes:
    """A real grey PNG of ``width`` x ``height`` pixels (a horizontal ramp), no dependency."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    line = bytes([0]) + bytes((255 * x // max(width - 1, 1)) for x in range(width))
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(line * height))
        + chunk(b"IEND", b"")
    )


def fake_section(ctx) -> Section:
    sec = Section("fake", "Fake section (test)")
    sec.p("a paragraph")
    sec.table(["a", "b"], [[1, 2.5]])
    sec.table(
        [f"a wide column header number {i}" for i in range(14)], [[f"cell {i} of a wide table" for i in range(14)]]
    )
    fig = ctx.fig_dir / "fake.png"
    fig.write_bytes(png(1600, 120))
    sec.fig(fig, "a figure wider than the page")
    sec.numbers += [
        row(
            "r2",
            "r2 (saddle-node of the 6-impact orbit, alpha = 3)",
            0.8214404475801397,
            2e-14,
            paper="r2",
            computed_text="0.8214404476",
            error_text="+- 2e-14 (Newton residual of the extended system)",
            explanation=LONG,
            where="Fig. 5 caption",
        ),
        row(
            "r2_fig6",
            "r2 against the r of Fig. 6",
            0.8214404475801397,
            2e-14,
            paper="r2_fig6",
            enclosure=(0.8214404475801, 0.8214404475802),
            explanation="decided by an enclosure",
        ),
        row("r1", "r1", 0.74139, 2e-5, paper="r1"),
        row("alpha1", "alpha1 (crisis of Fig. 8, r = 0.9)", 1.24363, 0.00053, paper="alpha1", explanation=LONG),
        row("mean_n", "<n>", 2461.0, 30.0, paper="mean_n"),
        row("kappa", "kappa", 0.95, 0.01, paper="kappa", error_text="+- 0.01 (bootstrap)"),
        row("decay_time", "decay time", 2590.0, 40.0, paper="decay_time"),
        row("phi_500", "phi", 0.011, 0.002, paper="phi_500"),
        row("phi_1000", "phi", None, paper="phi_1000", computed_text="fit failed"),
        row(
            "fig2_motion",
            "motion",
            -0.2,
            paper="fig2_motion",
            category="regular",
            computed_text="regular: periodic, 3 impacts per 1 driving period(s), lambda1 = -0.21",
        ),
        row("r2_impacts_per_period", "impacts per period", 6, paper="r2_impacts_per_period"),
        row(
            "track_agreement",
            "tracks",
            4e-13,
            paper=None,
            tolerance=1e-10,
            computed_text="max |dtau| = 4e-13, 0 wall/kind mismatches",
        ),
        row("release_T_post", "a row added later", 1234, 0, paper=None, error_text="0 (certified)"),
    ]
    return sec


def build_fake_report(out: Path, monkeypatch) -> Path:
    """Build the report with :func:`fake_section` as its only section into ``out``; return ``out``."""
    mod = types.ModuleType("gear_rattle_test_fake_section")
    mod.KEY, mod.TITLE, mod.build = "fake", "Fake section (test)", fake_section
    monkeypatch.setattr(builder, "section_modules", lambda: [mod])
    monkeypatch.setattr(builder, "environment", lambda: {"python": "test"})
    _, ok = builder.build_report("quick", out, progress=False, argv=["gear-rattle", "report"])
    assert ok
    return out
