"""The sensitivity of the oracle (issue 36 item 3): for each planted-bug class of tests/golden_mutants.py that has a
size, the smallest size the shipped suite detects (``gear-rattle check``) and the smallest the fuzzer detects within
its budget (``gear-rattle fuzz``, default 60 s), on one or more checkouts of the oracle (today against after).

The implementation under test is always this checkout's tests/mutant_impl.py, run by this interpreter: only the
oracle differs between checkouts (its suite, its checker, its fuzzer), called through the suite's protocol
(``COMMAND CASES_DIR OUT_DIR``).  A checkout is a folder with ``validation/golden/cases`` and ``.venv/bin/gear-rattle``.

Each class has a grid of sizes ordered from the largest error to the smallest (:data:`CLASSES`); detection is taken
as monotone along it and the smallest detected size is searched from a guess (the target for the suite, the
suite's answer for the fuzzer) by galloping and bisection (:func:`search`).  The fuzzer is random: the search uses
the first seed; the other seeds then run at the smallest detected size and the next one (and further while one of
them detects), and each size reports its detection rate.  A control (the base mutant, no planted error) must pass
the suite and the fuzzer on every checkout.

Usage (one command; progress on stderr, the JSON and the figure written as it goes)::

    python benchmarks/bench_sensitivity.py --checkout before=../before --checkout after=. \\
        [--classes restitution,digits,...] [--sizes restitution=1e-9,1e-12] [--seeds 1,2] [--budget 60] \\
        [--no-fuzz | --fuzz-on after] [--resume FILE] [--out FILE] [--figure FILE]
    python benchmarks/bench_sensitivity.py --plot-only FILE --figure FILE.png
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from gear_rattle.validation.io.atomic import write_atomic, write_text_atomic

ROOT = Path(__file__).resolve().parents[1]
#: The gap error of a correct float64 implementation at a wall (conditioning.GAP_ULPS steps of 2^-52).
GAP_ERROR = 2 * 2.0**-52
HALF_DECADES = tuple(float(f"{m}e{e}") for e in range(-7, -16, -1) for m in (3, 1) if not (m == 3 and e == -7))


@dataclass(frozen=True)
class SizedClass:
    """A planted-bug class with a size: ``mutant`` names tests/mutant_impl.py's mutant of a size, ``grid`` the sizes
    from the largest error to the smallest, ``float64`` the size float64 itself allows and ``target`` the goal
    (issue 36: within 10x of float64), ``unit`` what the size is."""

    name: str
    mutant: Callable[[float], str]
    grid: tuple[float, ...]
    float64: float
    target: float
    unit: str


def _relative(prefix: str, what: str) -> SizedClass:
    return SizedClass(prefix, lambda x: f"{prefix}-{x:g}", HALF_DECADES, 1e-14, 1e-13, f"relative error of {what}")


#: The classes.  float64 and target: a relative perturbation ~1e-14 and 1e-13 (a correct implementation errs by
#: ~1e-14 after a few impacts); printed digits 16 and 14; a contact tolerance of one gap error and ten (the
#: near-miss rule of the cases asks nothing closer to a wall than 10 gap errors); a fixed step: the duration of an
#: excursion GAP_ERROR (10 x GAP_ERROR) beyond a wall under an acceleration of 1, 2 sqrt(2 d); the multiple of the
#: modelled per-contact error: 1 and 10 (the tolerances' factor).
CLASSES: dict[str, SizedClass] = {
    c.name: c
    for c in (
        _relative("restitution", "r in every bounce"),
        _relative("two-pi", "2 pi in every phase reduction"),
        _relative("forcing", "the forcing amplitude alpha in the flights"),
        SizedClass("digits", lambda d: f"digits-{int(d)}", tuple(range(8, 17)), 16, 14, "significant digits printed"),
        SizedClass(
            "fixed-step",
            lambda h: f"fixed-step-{h:g}",
            (1.0, 0.3, 0.1, 0.03, 0.01, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5),
            2 * math.sqrt(2 * GAP_ERROR),
            2 * math.sqrt(2 * 10 * GAP_ERROR),
            "step of a fixed-step sign-change finder",
        ),
        SizedClass(
            "contact-tolerance",
            lambda x: f"contact-tolerance-{x:g}",
            (1e-6, 3e-7) + HALF_DECADES,
            GAP_ERROR,
            10 * GAP_ERROR,
            "distance to a wall at which a turning point is taken for a contact",
        ),
        SizedClass(
            "gap-scale",
            lambda k: f"gap-scale-{k:g}",
            (1000.0, 300.0, 100.0, 30.0, 10.0, 3.0, 1.0),
            1.0,
            10.0,
            "multiple of the modelled per-contact error (random signs)",
        ),
    )
}
DEFAULT_CLASSES = ("restitution", "digits", "two-pi", "forcing", "fixed-step", "contact-tolerance")
#: Exit status of check and fuzz when they detect (0: nothing found).
DETECTED = 1
#: Signature kinds of fuzz that say the implementation could not be scored (not a detection of its error).
NOT_SCORED = ("crash", "timeout", "missing output", "malformed")


def search(detect: Callable[[int], bool], n: int, guess: int = 0) -> int:
    """The largest index ``k < n`` with ``detect(k)`` (``-1`` if none), for a ``detect`` true up to ``k`` and false
    after it: galloping from ``guess`` in the direction of its answer, then bisection."""
    guess = min(max(guess, 0), n - 1)
    if detect(guess):
        lo, hi, step = guess, n, 1
        while lo + step < n and detect(lo + step):
            lo, step = lo + step, step * 2
        hi = min(lo + step, n)
    else:
        lo, hi, step = -1, guess, 1
        while hi - step >= 0 and not detect(hi - step):
            hi, step = hi - step, step * 2
        lo = max(hi - step, -1)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if detect(mid) else (lo, mid)
    return lo


@dataclass(frozen=True)
class Checkout:
    """An oracle: ``name`` (before, after), its ``root`` and its ``gear-rattle`` command."""

    name: str
    root: Path
    command: str

    @property
    def cases(self) -> Path:
        return self.root / "validation" / "golden" / "cases"

    def describe(self) -> dict:
        git = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=self.root, capture_output=True, text=True)
        ver = subprocess.run([self.command, "--version"], capture_output=True, text=True)
        return {"root": str(self.root), "commit": git.stdout.strip(), "version": ver.stdout.strip()}


def checkout(spec: str) -> Checkout:
    """``NAME=PATH`` to a :class:`Checkout` (``PATH/.venv/bin/gear-rattle``, else this interpreter's)."""
    name, _, path = spec.partition("=")
    if not name or not path:
        raise SystemExit(f"bench_sensitivity: error: --checkout {spec!r}: expected NAME=PATH")
    root = Path(path).resolve()
    cmd = root / ".venv" / "bin" / "gear-rattle"
    if not cmd.is_file():
        cmd = Path(sys.executable).parent / "gear-rattle"
    if not (root / "validation" / "golden" / "cases").is_dir():
        raise SystemExit(f"bench_sensitivity: error: --checkout {spec!r}: no validation/golden/cases there")
    return Checkout(name, root, str(cmd))


def impl_command(mutant: str, impl: Path) -> list[str]:
    """The mutant as an implementation: this interpreter running ``impl`` (tests/mutant_impl.py)."""
    return [sys.executable, str(impl), mutant]


def load() -> float:
    return round(os.getloadavg()[0], 2)


def suite_run(co: Checkout, mutant: str, impl: Path, timeout: float) -> dict:
    """The mutant's outputs on the checkout's suite, scored by its ``check``: detected, the failing cases."""
    t, l0 = time.time(), load()
    with tempfile.TemporaryDirectory(prefix="sens-suite-") as tmp:
        try:
            subprocess.run([*impl_command(mutant, impl), str(co.cases), tmp], check=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return {"detected": None, "error": f"timeout after {timeout:g} s", "seconds": round(time.time() - t, 1)}
        res = subprocess.run([co.command, "check", tmp, "--suite", str(co.cases)], capture_output=True, text=True)
    ids = {p.name for p in co.cases.iterdir() if p.is_dir()}
    verdicts = {w[0]: w[1] for w in (line.split() for line in res.stdout.splitlines()) if len(w) > 1 and w[0] in ids}
    failing = sorted(c[:4] for c, v in verdicts.items() if v != "PASS")
    return {
        "detected": res.returncode == DETECTED,
        "exit": res.returncode,
        "failing": failing,
        "cases": len(verdicts),
        "seconds": round(time.time() - t, 1),
        "load": l0,
    }


def _findings(summary: dict) -> list[dict]:
    """The fuzz summary's findings (``groups`` of today's fuzzer, ``failures`` of the former one), condensed."""
    out = []
    for g in summary.get("groups", summary.get("failures", [])):
        sig = g.get("signature") or {}
        out.append(
            {
                "kind": sig.get("kind", "value"),
                "signature": sig.get("text"),
                "scenario": g.get("scenario"),
                "message": g.get("message"),
                "found_after_s": g.get("found_after_s"),
                "input": g.get("input"),
            }
        )
    return out


def fuzz_run(co: Checkout, mutant: str, impl: Path, seed: int, budget: float) -> dict:
    """One ``fuzz`` run of the mutant on the checkout: detected (a finding other than a crash or timeout), the cases
    it scored, its first finding."""
    t, l0 = time.time(), load()
    with tempfile.TemporaryDirectory(prefix="sens-fuzz-") as tmp:
        cmd = [co.command, "fuzz", "--impl", shlex.join(impl_command(mutant, impl)), "--seed", str(seed)]
        cmd += ["--budget", f"{budget:g}", "--quiet", "--out", str(Path(tmp) / "found")]
        res = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp)
    text = res.stdout[res.stdout.find("{") :] if "{" in res.stdout else "{}"
    try:
        summary = json.loads(text)
    except json.JSONDecodeError:
        summary = {"error": res.stdout[-500:] + res.stderr[-500:]}
    found = _findings(summary)
    scored = [f for f in found if f["kind"] not in NOT_SCORED]
    return {
        "detected": res.returncode == DETECTED and bool(scored),
        "exit": res.returncode,
        "cases": summary.get("cases"),
        "elapsed_s": summary.get("elapsed_s"),
        "first": (scored or found or [None])[0],
        "findings": len(found),
        "error": summary.get("error") or (res.stderr.strip().splitlines()[-1:] or [None])[0]
        if res.returncode > 1
        else None,
        "seconds": round(time.time() - t, 1),
        "load": l0,
    }


class Bench:
    """The runs of one benchmark, cached by key (``--resume`` reuses a former result's runs) and saved as they
    come: :attr:`result` is the JSON written to ``out``."""

    def __init__(self, args: argparse.Namespace, checkouts: list[Checkout], old: dict | None):
        self.args, self.checkouts, self.impl = args, checkouts, Path(args.impl).resolve()
        self.described = {co.name: co.describe() for co in checkouts}
        self.result: dict = {
            "what": "the smallest planted error of each sized bug class the suite (check) and the fuzzer (fuzz, "
            "within its budget) detect, per checkout of the oracle (issue 36 item 3)",
            "date": time.strftime("%Y-%m-%d"),
            "command": " ".join(shlex.quote(a) for a in sys.argv),
            "machine": f"{os.cpu_count()} cores, shared (load average at each run)",
            "uptime_start": _uptime(),
            "budget_s": args.budget,
            "seeds": args.seeds,
            "implementation": {"impl": str(self.impl), "commit": _commit(self.impl.parent)},
            "checkouts": self.described,
            "control": {},
            "classes": {},
            "runs": {},
        }
        self.cache = dict((old or {}).get("runs", {}))

    def key(self, co: Checkout, kind: str, mutant: str, seed: int = 0) -> str:
        key = f"{co.name}|{kind}|{mutant}"
        return key + (f"|seed {seed}|{self.args.budget:g} s" if kind == "fuzz" else "")

    def get(self, co: Checkout, kind: str, mutant: str, seed: int = 0) -> dict | None:
        """The run's record if it was made (or resumed) in this benchmark."""
        return self.result["runs"].get(self.key(co, kind, mutant, seed))

    def run(self, co: Checkout, kind: str, mutant: str, seed: int = 0) -> dict:
        """The suite's (``kind`` suite) or the fuzzer's verdict on ``mutant``, cached."""
        key = self.key(co, kind, mutant, seed)
        if key in self.result["runs"]:
            return self.result["runs"][key]
        cached = key in self.cache
        if not cached:
            if kind == "suite":
                self.cache[key] = suite_run(co, mutant, self.impl, self.args.timeout)
            else:
                self.cache[key] = fuzz_run(co, mutant, self.impl, seed, self.args.budget)
            self.cache[key]["commit"] = self.described[co.name]["commit"]
        self.result["runs"][key] = self.cache[key]
        _progress(key, self.cache[key], cached)
        self.save()
        return self.cache[key]

    def fuzzes(self, co: Checkout) -> bool:
        """Whether the fuzzer runs on ``co`` (not with --no-fuzz; with --fuzz-on, only on the checkouts it names)."""
        return not self.args.no_fuzz and (not self.args.fuzz_on or co.name in self.args.fuzz_on)

    def save(self) -> None:
        self.result["uptime_end"] = _uptime()
        if self.args.out:
            write_text_atomic(
                self.args.out, json.dumps(self.result, indent=1, default=str) + "\n"
            )  # a kill keeps the last whole one (--resume)

    def control(self, co: Checkout) -> None:
        """The base mutant (no planted error) passes the suite, and the fuzzer with the first seed."""
        entry = {"suite": self.run(co, "suite", "base")}
        if self.fuzzes(co):
            entry["fuzz"] = self.run(co, "fuzz", "base", self.args.seeds[0])
        self.result["control"][co.name] = entry

    def suite_threshold(self, cls: SizedClass, grid: tuple[float, ...], co: Checkout) -> dict:
        detect = lambda i: bool(self.run(co, "suite", cls.mutant(grid[i]))["detected"])  # noqa: E731
        k = search(detect, len(grid), _nearest(grid, cls.target))
        seen = [(x, self.get(co, "suite", cls.mutant(x))) for x in grid]
        return {
            "smallest_detected": grid[k] if k >= 0 else None,
            "evaluated": [{"size": x, "detected": r["detected"], "failing": r.get("failing")} for x, r in seen if r],
            "index": k,
        }

    def fuzz_threshold(self, cls: SizedClass, grid: tuple[float, ...], co: Checkout, guess: int) -> dict:
        seeds = self.args.seeds
        detect = lambda i, s=seeds[0]: bool(self.run(co, "fuzz", cls.mutant(grid[i]), s)["detected"])  # noqa: E731
        k = search(detect, len(grid), guess)
        # the other seeds at the smallest detected size and below it, while one of them detects
        i = max(k, 0)
        while i < len(grid) and len(seeds) > 1:
            hits = [detect(i, s) for s in seeds]
            if i > k and not any(hits):
                break
            i += 1
        rates: dict = {}
        for x in grid:
            got = [r for r in (self.get(co, "fuzz", cls.mutant(x), s) for s in seeds) if r]
            if got:
                rates[f"{x:g}"] = {
                    "detected": sum(bool(r["detected"]) for r in got),
                    "runs": len(got),
                    "cases": [r.get("cases") for r in got],
                    "first": [r["first"]["scenario"] if r.get("first") else None for r in got],
                }
        any_hit = [x for x in grid if rates.get(f"{x:g}", {}).get("detected")]
        every = [x for x in grid if f"{x:g}" in rates and rates[f"{x:g}"]["detected"] == rates[f"{x:g}"]["runs"]]
        return {
            "smallest_detected": any_hit[-1] if any_hit else None,
            "smallest_detected_by_every_seed": every[-1] if every else None,
            "rates": rates,
        }

    def measure(self, name: str, grid: tuple[float, ...]) -> None:
        cls = CLASSES[name]
        entry = {"unit": cls.unit, "grid": list(grid), "float64": cls.float64, "target": cls.target, "results": {}}
        self.result["classes"][name] = entry
        for co in self.checkouts:
            res = entry["results"][co.name] = {"suite": self.suite_threshold(cls, grid, co)}
            self.save()
            if self.fuzzes(co):
                guess = res["suite"].pop("index")
                res["fuzz"] = self.fuzz_threshold(cls, grid, co, guess if guess >= 0 else 0)
            res["suite"].pop("index", None)
            self.save()


def _nearest(grid: tuple[float, ...], x: float) -> int:
    return min(range(len(grid)), key=lambda i: abs(math.log(grid[i] / x)))


def _uptime() -> str:
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def _commit(path: Path) -> str:
    return subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], cwd=path, capture_output=True, text=True
    ).stdout.strip()


def _progress(key: str, rec: dict, cached: bool) -> None:
    verdict = {True: "detected", False: "passes", None: "error"}[rec.get("detected")]
    more = f" failing {','.join(rec['failing'])}" if rec.get("failing") else ""
    if rec.get("first"):
        more = (
            f" {rec.get('cases')} cases, first: {rec['first'].get('scenario')} ({rec['first'].get('signature') or ''})"
        )
    elif "cases" in rec and "elapsed_s" in rec:
        more = f" {rec.get('cases')} cases"
    when = "resumed" if cached else f"{time.strftime('%H:%M:%S')} load {rec.get('load')}"
    print(f"[{when}] {key}: {verdict} in {rec.get('seconds')} s{more}", file=sys.stderr, flush=True)


#: Marker styles of the checkouts, in the order given (the first one open: "today"; the next filled).
STYLES = (
    {"mfc": "white", "color": "tab:gray"},
    {"mfc": "tab:blue", "color": "tab:blue"},
    {"mfc": "tab:orange", "color": "tab:orange"},
)


def _point(entry: dict, grid: list[float]) -> tuple[float, str]:
    """Where a smallest detected size is drawn and its marker: ``o`` found, ``v`` at or below the grid's smallest
    size, ``^`` none detected (drawn just beyond the grid's largest)."""
    x = entry.get("smallest_detected")
    if x is None:
        beyond = grid[0] - 1 if grid[0] < grid[-1] else grid[0] * 3
        return beyond, "^"
    return x, "v" if x == grid[-1] else "o"


def plot(result: dict, path: Path) -> None:
    """One panel per class: the smallest size the suite and the fuzzer detect on each checkout, with the target
    and float64's limit (digits on an inverted axis: down is always a smaller error)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(result["classes"])
    cols = min(4, len(names))
    rows = -(-len(names) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.3 * rows), squeeze=False)
    for ax, name in zip(axes.flat, names):
        c = result["classes"][name]
        grid = c["grid"]
        for k, (co, res) in enumerate(c["results"].items()):
            for j, part in enumerate(("suite", "fuzz")):
                if part not in res:
                    continue
                y, m = _point(res[part], grid)
                st = STYLES[k % len(STYLES)]
                ax.plot(
                    [j + 0.12 * (k - 0.5)],
                    [y],
                    m,
                    ms=8,
                    mew=1.5,
                    mec=st["color"],
                    mfc=st["mfc"],
                    label=co if j == 0 else None,
                )
        ax.axhline(c["target"], color="tab:green", ls="--", lw=1, label="target (10x float64)")
        ax.axhline(c["float64"], color="black", ls=":", lw=1, label="float64")
        ax.set_xticks([0, 1], ["suite", "fuzz"])
        ax.set_xlim(-0.6, 1.6)
        if name == "digits":
            ax.invert_yaxis()
        else:
            ax.set_yscale("log")
        ax.set_title(name, fontsize=10)
        ax.set_ylabel(c["unit"], fontsize=7)
        ax.grid(True, axis="y", alpha=0.3)
    for ax in list(axes.flat)[len(names) :]:
        ax.axis("off")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=8, frameon=False)
    fig.suptitle(
        f"Smallest planted error detected ({result.get('date')}, fuzz budget {result.get('budget_s'):g} s)\n"
        "o found, v the grid's smallest, ^ none on the grid; down is a smaller error",
        fontsize=9,
    )
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    write_atomic(path, lambda fh: fig.savefig(fh, format="png", dpi=110))
    plt.close(fig)


def _sizes(specs: list[str]) -> dict[str, tuple[float, ...]]:
    """``CLASS=a,b,...`` to the class's sizes, ordered as its grid (the largest error first)."""
    out = {}
    for spec in specs:
        name, _, values = spec.partition("=")
        if name not in CLASSES or not values:
            raise SystemExit(
                f"bench_sensitivity: error: --sizes {spec!r}: expected CLASS=SIZE,... with CLASS in "
                f"{', '.join(CLASSES)}"
            )
        grid = CLASSES[name].grid
        sizes = sorted({float(v) for v in values.split(",")}, reverse=grid[0] > grid[-1])
        out[name] = tuple(sizes)
    return out


def parse(argv: list[str] | None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--checkout",
        action="append",
        default=[],
        metavar="NAME=PATH",
        help="an oracle to measure, in order (default: after=this checkout)",
    )
    ap.add_argument("--classes", default=",".join(DEFAULT_CLASSES), help=f"of {', '.join(CLASSES)}")
    ap.add_argument("--sizes", action="append", default=[], metavar="CLASS=SIZE,...", help="a class's sizes")
    ap.add_argument("--seeds", default="1,2", help="fuzz seeds (the first one searches)")
    ap.add_argument("--budget", type=float, default=60.0, help="fuzz --budget (default: fuzz's default, 60)")
    ap.add_argument("--timeout", type=float, default=1800.0, help="seconds a mutant may take on the suite")
    ap.add_argument("--no-fuzz", action="store_true", help="the suite only")
    ap.add_argument("--fuzz-on", default="", metavar="NAME,...", help="fuzz only these checkouts (default: every one)")
    ap.add_argument("--no-control", action="store_true", help="skip the base mutant's runs")
    ap.add_argument("--impl", default=str(ROOT / "tests" / "mutant_impl.py"), help="the mutants' implementation")
    ap.add_argument(
        "--resume", default=None, help="a former result whose runs are reused (by checkout name: the same code)"
    )
    ap.add_argument(
        "--out", default=str(ROOT / "benchmarks" / "results" / f"sensitivity_{time.strftime('%Y-%m-%d')}.json")
    )
    ap.add_argument("--figure", default=None, help="the PNG (default: --out with .png)")
    ap.add_argument("--plot-only", default=None, metavar="JSON", help="only draw the figure of a result")
    a = ap.parse_args(argv)
    a.seeds = [int(s) for s in a.seeds.split(",") if s]
    a.fuzz_on = [n for n in a.fuzz_on.split(",") if n]
    return a


def main(argv: list[str] | None = None) -> int:
    a = parse(argv)
    if a.plot_only:
        plot(json.loads(Path(a.plot_only).read_text()), Path(a.figure or Path(a.plot_only).with_suffix(".png")))
        return 0
    checkouts = [checkout(s) for s in a.checkout] or [checkout(f"after={ROOT}")]
    unknown = [n for n in a.fuzz_on if n not in {co.name for co in checkouts}]
    if unknown:
        raise SystemExit(f"bench_sensitivity: error: --fuzz-on: {unknown} are not among the --checkout names")
    classes = [c for c in a.classes.split(",") if c]
    unknown = [c for c in classes if c not in CLASSES]
    if unknown:
        raise SystemExit(f"bench_sensitivity: error: --classes: unknown {unknown}; allowed {', '.join(CLASSES)}")
    sizes = _sizes(a.sizes)
    old = json.loads(Path(a.resume).read_text()) if a.resume else None
    bench = Bench(a, checkouts, old)
    if not a.no_control:
        for co in checkouts:
            bench.control(co)
    for name in classes:
        bench.measure(name, sizes.get(name, CLASSES[name].grid))
    bench.save()
    plot(bench.result, Path(a.figure or Path(a.out).with_suffix(".png")))
    for name, c in bench.result["classes"].items():
        for co, res in c["results"].items():
            found = {part: res[part]["smallest_detected"] for part in ("suite", "fuzz") if part in res}
            print(f"{name:18s} {co:8s} " + "  ".join(f"{k} {v if v is not None else 'none'}" for k, v in found.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
