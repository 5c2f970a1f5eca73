"""Run the report's sections and write ``report.md``, a self-contained ``report.html``, ``summary.json``
and ``document.json`` (the document model, from which :func:`rerender` draws the report again
without computing: ``python -m gear_rattle.validation.report rerender DIR``).

Sections are the modules of :func:`section_modules` (keys :data:`SECTION_KEYS`); each defines ``KEY``, ``TITLE`` and
``build(ctx) -> Section``.  A section that raises is kept in the report, marked FAILED with its
error, and makes the command exit non-zero: a failure is reported, never hidden.
"""

from __future__ import annotations

import importlib
import os
import platform
import sys
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType

from ...core.checks import check_choice
from ..io import read_json, write_json
from ..profiles import PROFILE_NAMES
from ..io.atomic import DEVICE_ERRNOS, outputs, read_manifest, staged, write_text_atomic
from .verdict import Z_AGREE
from .docjson import document_json, sections_from_json
from .document import Document, Section, check_keys, render_html, render_markdown, verdict_counts

#: The sections' keys (``--sections``), in report order: each module's ``KEY``, its name after ``sec_``
#: (known without importing the sections, which import the analyses: ``gear-rattle report --help``).
SECTION_KEYS = ["timeseries", "crosstrack", "dynamics", "transients"]


def section_modules() -> list[ModuleType]:
    """The section modules, in report order (:data:`SECTION_KEYS`).  Imported by import statements, which
    the import contract and tests/test_import_cycles.py see (a module named in a string is an edge
    neither sees), when the report is built."""
    from . import sec_crosstrack, sec_dynamics, sec_timeseries, sec_transients

    return [sec_timeseries, sec_crosstrack, sec_dynamics, sec_transients]


PROFILES = PROFILE_NAMES  # the run sizes of each: validation.profiles


@dataclass
class Context:
    """What a section needs: the profile, the output directory (figures go in ``fig_dir``), the seed,
    whether to print progress, and a log of the computations run (for the provenance section)."""

    profile: str
    out_dir: Path
    seed: int = 20040101
    progress: bool = True
    log: list = field(default_factory=list)

    @property
    def quick(self) -> bool:
        return self.profile == "quick"

    @property
    def fig_dir(self) -> Path:
        d = self.out_dir / "figures"
        d.mkdir(parents=True, exist_ok=True)
        return d

    def say(self, text: str) -> None:
        if self.progress:
            from ..progress import clear_status

            clear_status()
            print(f"[report] {text}", file=sys.stderr, flush=True)


def speed_reference(n: int = 10_000_000) -> float:
    """Seconds for a pure-Python loop of ``n`` integer additions: a rough single-core speed of the machine
    at the time of the run, so that run times can be compared across machines and days (2.3-2.9 s on
    the shared 2-core development machine on 2026-11-23).  Recorded in the header as
    ``speed_reference_s``."""
    t0 = time.perf_counter()
    acc = 0
    for i in range(n):
        acc += i
    return round(time.perf_counter() - t0, 3)


def environment() -> dict:
    """Versions, machine and device, for the report header."""
    import jax
    import numpy
    import scipy

    env = {
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "machine": platform.machine(),
        "cpu_count": os.cpu_count(),
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "jax": jax.__version__,
        "jax_devices": ", ".join(str(d) for d in jax.devices()),
        "jax_enable_x64": bool(jax.config.jax_enable_x64),  # type: ignore[attr-defined]  # jax.config: dynamic attrs
    }
    for mod in ("diffrax", "optimistix", "matplotlib", "mpmath"):
        try:
            env[mod] = importlib.import_module(mod).__version__
        except Exception:  # pragma: no cover - optional
            env[mod] = "not installed"
    env["speed_reference_s"] = speed_reference()
    env["git_commit"] = git_commit()
    return env


def git_commit() -> str:
    """The commit of this code, with " (with uncommitted changes)" when the tree is dirty; "unknown"
    outside a git checkout."""
    try:
        import subprocess

        root = Path(__file__).resolve().parents[2]
        commit = (
            subprocess.run(
                ["git", "rev-parse", "HEAD"], capture_output=True, text=True, cwd=root, timeout=5
            ).stdout.strip()
            or "unknown"
        )
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            cwd=root,
            timeout=5,
        ).stdout.strip()
        return commit + (" (with uncommitted changes)" if dirty and commit != "unknown" else "")
    except Exception:  # pragma: no cover
        return "unknown"


def summary_json(sections: list[Section], **header) -> dict:
    """summary.json: the run's header, the sections' status, the verdict counts and one entry per summary
    row (stable ``key``, numeric ``value``/``error``, the paper's value/error/kind; see docs/report.md)."""
    return {
        **header,
        "sections": [
            {"key": s.key, "title": s.title, "ok": s.ok, "seconds": s.seconds, "error": s.error} for s in sections
        ],
        "counts": verdict_counts(sections),
        "numbers": [n.as_json(s.title) for s in sections for n in s.numbers],
    }


def build_report(
    profile: str = "quick",
    out_dir: str | Path = "report",
    sections: list[str] | None = None,
    seed: int = 20040101,
    progress: bool = True,
    argv: list[str] | None = None,
) -> tuple[Path, bool]:
    """Run the sections and write the report; return ``(path of report.html, all sections ok)``."""
    check_choice("profile", profile, PROFILES)
    mods = section_modules()
    if sections:
        unknown = set(sections) - {m.KEY for m in mods}
        if unknown:
            raise ValueError(f"sections={sorted(unknown)} not known: allowed {', '.join(m.KEY for m in mods)}")
        mods = [m for m in mods if m.KEY in sections]
    out = Path(out_dir)
    with staged(out, "report") as stage:  # every file moved into out at the end; nothing else there touched
        path, ok = _run_sections(mods, profile, stage, seed, progress, argv)
    return out / path.name, ok


def _run_sections(mods, profile: str, out: Path, seed: int, progress: bool, argv) -> tuple[Path, bool]:
    ctx = Context(profile=profile, out_dir=out, seed=seed, progress=progress)
    # the commit and the machine are recorded before the run (a commit made while it runs is not its code)
    env = environment()
    t_all = time.perf_counter()
    done: list[Section] = []
    for m in mods:
        ctx.say(f"{m.TITLE} ...")
        t0 = time.perf_counter()
        try:
            sec = m.build(ctx)
        except Exception as e:  # keep going, report the failure
            if isinstance(e, OSError) and e.errno in DEVICE_ERRNOS:  # a full disk ends the report in one line
                raise
            sec = Section(m.KEY, m.TITLE, ok=False, error=f"{type(e).__name__}: {e}\n{traceback.format_exc(limit=6)}")
        sec.seconds = time.perf_counter() - t0
        ctx.say(f"{m.TITLE}: {'ok' if sec.ok else 'FAILED'} in {sec.seconds:.1f} s")
        done.append(sec)
    total = time.perf_counter() - t_all
    cmd = " ".join(argv) if argv is not None else " ".join(sys.argv)
    header = {"profile": profile, "seed": seed, "seconds": total, "environment": env, "command": cmd}
    return write_report(out, header, done), all(s.ok for s in done)


def compose(header: dict, sections: list[Section]) -> Document:
    """The page's text around the sections, from the run's header (profile, seed, seconds, environment,
    command): the title, the introduction, and the run's provenance with how verdicts are reached."""
    profile = header["profile"]
    intro = [
        "Reproduction of de Souza, Caldas, Viana and Balthazar, Chaos, Solitons & Fractals 21 (2004) 763-772, "
        "by the gear-rattle reference implementation. Every computed number and figure below was produced "
        "by the run that wrote this page; the paper's values are quoted from the paper's text."
    ]
    about = [
        f"Profile: {profile}. Seed: {header['seed']}. Total run time: {header['seconds']:.1f} s. "
        f"Command: {header['command']}",
        "Environment: " + "; ".join(f"{k} {v}" for k, v in header["environment"].items()),
        "Run times per section: " + "; ".join(f"{s.title} {s.seconds:.1f} s" for s in sections),
        f"How the verdicts are reached (validation/report/verdict.py, docs/report.md): a value is compared by "
        f"z = (ours - paper) / sqrt(our error^2 + paper error^2), the paper error being the one it states or else "
        f"the rounding of its last printed digit; it agrees when |z| <= {Z_AGREE:g}. A bound the paper states "
        f"(the r or alpha it ran, '>~' or '<~' a critical value) is checked strictly in its direction against the "
        f"printed value: satisfied or violated, with the margin (ours - paper) in absolute terms and in units of "
        f"the paper's last printed digit, no z-score; 'satisfied (proven)' where a proven enclosure of our value "
        f"lies wholly on the bound's side. Checks of this implementation that the paper does not state are 'not "
        f"compared' and carry a separate pass/fail against their stated tolerance.",
    ]
    if header.get("rerendered"):
        about.append(
            f"This page was drawn again from document.json by commit {header['rerendered']['git_commit']}, "
            "with that commit's verdict rules and layout; the numbers, texts and figures are those of the "
            "run above (nothing was recomputed)."
        )
    return Document(f"gear-rattle validation report ({profile} profile)", intro, about, sections)


def write_report(out: Path, header: dict, sections: list[Section]) -> Path:
    """Write report.md, report.html, summary.json and document.json in ``out``; return report.html's path."""
    check_keys(sections)
    doc = compose(header, sections)
    write_text_atomic(out / "report.md", render_markdown(doc, out))
    html_path = out / "report.html"
    write_text_atomic(html_path, render_html(doc))
    write_json(out / "summary.json", summary_json(sections, **header))
    write_json(out / "document.json", document_json(header, sections, out), ensure_ascii=False)
    return html_path


def rerender(out_dir: str | Path) -> Path:
    """Draw a written report again from its ``document.json`` (no computation): every row is judged again
    by today's :mod:`.verdict` and the page laid out by today's :mod:`.document`; the figures are
    the files already in ``out_dir``.  The header gains ``rerendered`` (the commit that drew it), and
    the page says so.  Returns report.html's path."""
    out = Path(out_dir)
    src = out / "document.json"
    if not src.is_file():
        raise ValueError(f"out_dir={str(out)!r} has no document.json: allowed a folder written by gear-rattle report")
    read_manifest(out, "report")  # a folder whose files mix two runs is refused (ValueError naming it)
    header, sections = sections_from_json(read_json(src), out)
    with outputs("report", out, merge=True):  # the four files together, the manifest updated
        return write_report(out, {**header, "rerendered": {"git_commit": git_commit()}}, sections)


__all__ = [
    "SECTION_KEYS",
    "section_modules",
    "PROFILES",
    "Context",
    "speed_reference",
    "environment",
    "git_commit",
    "summary_json",
    "build_report",
    "compose",
    "write_report",
    "rerender",
]
