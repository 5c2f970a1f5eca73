"""A differential fuzzer: another implementation against certified cases on demand (``gear-rattle fuzz``;
docs/golden.md, "Fuzzing an implementation").

The protocol: the implementation is a command ``COMMAND CASES_DIR OUT_DIR`` that runs every case folder of
CASES_DIR (``settings.json`` in the suite's layout; no ``expected.csv``) and writes
``OUT_DIR/<case-id>.csv`` -- as it runs the shipped suite.  The fuzzer

1. draws *recipes* with Hypothesis (:mod:`.scenarios`: :func:`~.scenarios.draw_recipes`, reproducible
   by the seed): a scenario of the registry :data:`~.scenarios.SCENARIOS` that reaches a hard place on
   purpose, and its numbers, from which :func:`~.scenarios.construct` builds an input;
2. builds each input's certified case (:func:`ondemand.build_user_case`: every tolerance rule and the
   horizon rule of ``gear-rattle case``);
3. runs the implementation on a batch of cases (one process per batch), with a timeout;
4. scores every output with the suite's scorer (:func:`suite.score_file`);
5. shrinks each failing input (:func:`shrink`: fewer impacts, simpler numbers, the paper's parameters; each
   round of candidates one more batch) and writes the smallest failing case, a golden-format folder, to the
   output directory.

An implementation that exits with an error, outlives the timeout, or writes a missing or malformed file
is a :class:`ImplementationError` (one line): the fuzzer stops with it.
"""

from __future__ import annotations

import json
import shlex
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

from ...core.params import PARAM_NAMES
from . import generate, ondemand
from .ondemand import CaseError, CaseInput, UserCase
from .scenarios import PAPER_SETS, SCENARIOS, construct, draw_recipes
from .suite import MalformedFile, load_case, score_file

#: Cases per batch (one process of the implementation each), seconds a batch may take by default.
BATCH, TIMEOUT = 24, 300.0
#: Seconds the shrinking of one failure may take (it usually stops earlier: no simpler candidate fails);
#: at most the budget.
SHRINK_TIME = 90.0


class ImplementationError(Exception):
    """The implementation crashed, timed out, or wrote a missing or malformed file (one line)."""


# ---------------------------------------------------------------------------------------------
# running the implementation


def split_command(command: str) -> list[str]:
    """``COMMAND`` as an argument list (shell words); ``ValueError`` when empty or unbalanced."""
    try:
        words = shlex.split(command)
    except ValueError as e:
        raise ValueError(f"--impl {command!r}: {e}") from None
    if not words:
        raise ValueError("--impl is empty: allowed a command, called as COMMAND CASES_DIR OUT_DIR")
    return words


def run_implementation(command: list[str], cases: list[UserCase], timeout: float, work: Path) -> dict:
    """Run the implementation once on ``cases`` (their settings only) and score each output with the suite's
    scorer; returns ``{id: CaseScore}``.  :class:`ImplementationError` on a crash, a timeout, or a missing
    or malformed file."""
    if work.exists():
        shutil.rmtree(work)
    given, ref, out = work / "cases", work / "reference", work / "out"
    out.mkdir(parents=True)
    for c in cases:
        (given / c.input.id).mkdir(parents=True)
        (given / c.input.id / "settings.json").write_text(json.dumps(c.settings, indent=1) + "\n")
        ondemand.write_user_case(ref, c)
    try:
        proc = subprocess.run(
            [*command, str(given), str(out)], capture_output=True, text=True, timeout=timeout, stdin=subprocess.DEVNULL
        )
    except subprocess.TimeoutExpired:
        raise ImplementationError(
            f"the implementation did not finish {len(cases)} cases within {timeout:g} s (--timeout)"
        ) from None
    except OSError as e:
        raise ImplementationError(f"cannot start the implementation {command[0]!r}: {e.strerror or e}") from None
    if proc.returncode != 0:
        tail = (proc.stderr or proc.stdout or "").strip().splitlines()
        raise ImplementationError(
            f"the implementation exited with status {proc.returncode} on {len(cases)} cases"
            + (f": {tail[-1][:300]}" if tail else "")
        )
    scores = {}
    for c in cases:
        try:
            sc = score_file(load_case(ref / c.input.id), out / f"{c.input.id}.csv")
        except MalformedFile as e:
            raise ImplementationError(f"malformed output: {' '.join(str(e).split())[:400]}") from None
        sc.message = sc.message.replace(str(out), "OUT_DIR")  # the batch's folder is temporary
        scores[c.input.id] = sc
    return scores


# ---------------------------------------------------------------------------------------------
# shrinking


def complexity(inp: CaseInput) -> tuple:
    """The order of the shrinker (smaller is simpler): impacts, then the significant digits of the numbers,
    then the parameters that differ from the nearest paper set."""
    nums = [inp.params.alpha, inp.params.beta, inp.params.gamma, inp.params.r, inp.tau0, inp.sdot0]
    nums += [] if inp.s0 is None else [inp.s0]
    digits = sum(_digits(x) for x in nums)
    off = min(sum(getattr(inp.params, k) != getattr(q, k) for k in PARAM_NAMES) for q in PAPER_SETS)
    return (inp.impacts, digits, off)


def _digits(x: float) -> int:
    """Significant digits of the shortest repr of ``x`` (0 for 0)."""
    if x == 0:
        return 0
    m = repr(abs(x)).split("e")[0].replace(".", "").strip("0")
    return len(m)


def shrink_candidates(inp: CaseInput, fail_impact: int | None) -> list[CaseInput]:
    """Simpler inputs to try (each one change): fewer impacts (down to the first failing one, halves),
    numbers with fewer significant digits, parameters of a paper set."""
    out: list[CaseInput] = []
    seen = {inp}

    def add(**ch):
        try:
            c = ondemand.case_input(inp.id, **{**_fields(inp), **ch})
        except ValueError:
            return
        if c not in seen and complexity(c) < complexity(inp):
            seen.add(c)
            out.append(c)

    n, f = inp.impacts, fail_impact
    near = set() if f is None else {f - 1, f, f + 1, f + 2}
    for k in sorted({0, 1, 2, n // 8, n // 4, n // 2, (3 * n) // 4, n - 1} | near):
        if 0 <= k < n:
            add(impacts=k)
    for name in (*PARAM_NAMES, "tau0", "sdot0", "s0"):
        x = _fields(inp)[name]
        if x is None:
            continue
        for d in range(1, _digits(x)):
            add(**{name: float(f"{x:.{d}g}")})
        if name in ("gamma", "tau0"):
            add(**{name: 0.0})
    for q in PAPER_SETS:
        add(**q.as_dict())
        for name in PARAM_NAMES:
            add(**{name: getattr(q, name)})
    return out


def _fields(inp: CaseInput) -> dict:
    p = inp.params
    return {
        **p.as_dict(),
        "tau0": inp.tau0,
        "sdot0": inp.sdot0,
        "impacts": inp.impacts,
        "s0": inp.s0,
        "stick_time": inp.stick_time,
    }


def first_failing_impact(case: UserCase, score) -> int | None:
    """The impact index of the first failing row of a score (``None`` when not known)."""
    import csv

    rows = list(csv.DictReader(case.expected.splitlines()))
    line = None
    for c in score.columns.values():
        if not c.passed and c.first_row >= 0:
            line = c.first_row if line is None else min(line, c.first_row)
    if line is None and "line " in score.message:
        try:
            line = int(score.message.split("line ")[1].split()[0]) - 2
        except (ValueError, IndexError):
            return None
    return int(rows[min(line, len(rows) - 1)]["n"]) if line is not None and rows else None


@dataclass
class Failure:
    """A failing case found and shrunk."""

    case: UserCase
    message: str
    scenario: str
    found_after_s: float
    original: CaseInput
    shrink_rounds: int = 0
    folder: str = ""

    def summary(self) -> dict:
        return {
            "id": self.case.input.id,
            "folder": self.folder,
            "scenario": self.scenario,
            "message": self.message,
            "found_after_s": round(self.found_after_s, 2),
            "impacts": self.case.settings["n_impacts"],
            "rows": self.case.settings["expected_rows"],
            "input": self.case.input.as_dict(),
            "original_input": self.original.as_dict(),
            "shrink_rounds": self.shrink_rounds,
        }


def _merged(inp: CaseInput, failing: list[CaseInput]) -> CaseInput | None:
    """``inp`` with every change of the failing candidates at once (per field the simplest failing value;
    the fewest impacts), or ``None`` where that is one of them or not a valid input."""
    fields = _fields(inp)
    for c in failing:
        for k, v in _fields(c).items():
            if v == _fields(inp)[k]:
                continue
            if k == "impacts":
                fields[k] = min(fields[k], v)
            elif k in PARAM_NAMES and fields[k] != _fields(inp)[k]:
                continue  # a paper set's parameters: the first one found
            elif fields[k] == _fields(inp)[k] or _digits(v) < _digits(fields[k]):
                fields[k] = v
    try:
        m = ondemand.case_input(inp.id, **fields)
    except ValueError:
        return None
    return None if m in failing else m


def shrink(
    inp: CaseInput, case: UserCase, message: str, evaluate: Callable, fail_impact: int | None, deadline: float
) -> tuple[UserCase, str, int]:
    """The smallest failing case reachable by :func:`shrink_candidates` rounds, until no candidate fails or the
    deadline; returns ``(case, its failure message, rounds)``.  Each round runs every candidate of the current
    input in one batch, then (one more batch) all their failing changes at once; it keeps that merged input
    where it fails, else the simplest failing candidate (:func:`complexity`)."""
    rounds = 0
    while time.monotonic() < deadline:
        built = _build([replace(c, id=f"{inp.id}-s{k}") for k, c in enumerate(shrink_candidates(inp, fail_impact))])
        if not built:
            break
        scores = evaluate(built)
        failing = [b for b in built if not scores[b.input.id].passed]
        if not failing:
            break
        best = min(failing, key=lambda b: complexity(b.input))
        sc = scores[best.input.id]
        merged = _merged(replace(inp, id=f"{inp.id}-m"), [b.input for b in failing])
        if merged is not None and complexity(merged) < complexity(best.input) and time.monotonic() < deadline:
            mb = _build([merged])
            msc = evaluate(mb)[merged.id] if mb else None
            if msc is not None and not msc.passed:
                best, sc = mb[0], msc
        rounds += 1
        inp = replace(best.input, id=inp.id)
        case, message, fail_impact = _renamed(best, inp.id), sc.message, first_failing_impact(best, sc)
    return case, message, rounds


def _build(inputs: list[CaseInput]) -> list[UserCase]:
    """The cases of ``inputs`` that can be built (:func:`ondemand.build_user_case`)."""
    out = []
    for c in inputs:
        try:
            out.append(ondemand.build_user_case(c))
        except CaseError:
            continue
    return out


def _renamed(case: UserCase, id: str) -> UserCase:
    settings = {**case.settings, "id": id}
    return replace(case, input=replace(case.input, id=id), settings=settings, provenance={**case.provenance, "id": id})


# ---------------------------------------------------------------------------------------------
# the loop


@dataclass
class FuzzResult:
    """What a run found: ``failures`` (shrunk, written), the cases run, batches, scenarios drawn."""

    failures: list = field(default_factory=list)
    cases: int = 0
    batches: int = 0
    drawn: int = 0
    skipped: int = 0
    scenarios: dict = field(default_factory=dict)
    elapsed: float = 0.0
    error: str = ""


def fuzz(
    command: list[str],
    *,
    seed: int = 0,
    budget: float = 60.0,
    out: Path | None = None,
    keep_going: bool = False,
    timeout: float = TIMEOUT,
    batch: int = BATCH,
    scenarios: list[str] | None = None,
    progress: Callable | None = None,
    write: Callable[[Path, str], object] = generate.write_plain,
    written: Callable[[], object] | None = None,
) -> FuzzResult:
    """Fuzz the implementation ``command`` for ``budget`` seconds (module docstring); failures are written
    under ``out`` as golden-format case folders (``fuzz-<seed>-<k>``) with an ``index.json``.  Stops at the
    first failure (after shrinking it) unless ``keep_going``; ``progress(cases, failures)`` after each batch.
    The failing cases are written through ``write(path, text)`` and, after each, ``written()`` is called
    (the command line passes its atomic writer and the call that moves a found case into place at once).
    An :class:`ImplementationError` ends the run: ``result.error``."""
    t0 = time.monotonic()
    deadline = t0 + budget
    res = FuzzResult()
    allowed = scenarios or list(SCENARIOS)
    with tempfile.TemporaryDirectory(prefix="gear-rattle-fuzz-") as tmp:
        work = Path(tmp)

        def evaluate(cases: list[UserCase]) -> dict:
            res.batches += 1
            return run_implementation(command, cases, timeout, work / f"b{res.batches}")

        round_ = 0
        try:
            while time.monotonic() < deadline:
                recipes = draw_recipes(seed * 100_003 + round_, batch, allowed)
                round_ += 1
                cases: list[tuple[UserCase, str]] = []
                for rec in recipes:
                    if len(cases) >= batch or time.monotonic() >= deadline:
                        break
                    res.drawn += 1
                    inp = construct(rec, f"fuzz-{seed}-{res.drawn:06d}")
                    if inp is None:
                        res.skipped += 1
                        continue
                    try:
                        cases.append((ondemand.build_user_case(inp), rec["scenario"]))
                    except CaseError:
                        res.skipped += 1
                        continue
                    res.scenarios[rec["scenario"]] = res.scenarios.get(rec["scenario"], 0) + 1
                if not cases:
                    continue
                scores = evaluate([c for c, _ in cases])
                res.cases += len(cases)
                for c, scen in cases:
                    sc = scores[c.input.id]
                    if sc.passed:
                        continue
                    found = time.monotonic() - t0
                    shrunk, msg, rounds = shrink(
                        c.input,
                        c,
                        sc.message,
                        evaluate,
                        first_failing_impact(c, sc),
                        time.monotonic() + min(budget, SHRINK_TIME),
                    )
                    f = Failure(shrunk, msg, scen, found, c.input, rounds)
                    if out is not None:
                        f.folder = str(ondemand.write_user_case(out, _with_fuzz_notes(shrunk, f, seed), write))
                        if written is not None:
                            written()  # in place before the index lists and digests the folders
                        ondemand.update_index(out, write)
                        if written is not None:
                            written()
                    res.failures.append(f)
                    if not keep_going:
                        break
                if progress is not None:
                    progress(res.cases, len(res.failures))
                if res.failures and not keep_going:
                    break
        except ImplementationError as e:
            res.error = str(e)
    res.elapsed = time.monotonic() - t0
    return res


def _with_fuzz_notes(case: UserCase, f: Failure, seed: int) -> UserCase:
    """The case with ``notes.fuzz`` (how it was found) in its settings: a regression case to keep."""
    notes = {
        **case.settings["notes"],
        "fuzz": {
            "found_by": f"gear-rattle fuzz --seed {seed}",
            "scenario": f.scenario,
            "failure": f.message,
            "original_input": f.original.as_dict(),
            "shrink_rounds": f.shrink_rounds,
        },
    }
    settings = {**case.settings, "notes": notes, "tags": [*case.settings["tags"], "fuzz", f.scenario]}
    return replace(case, settings=settings)
