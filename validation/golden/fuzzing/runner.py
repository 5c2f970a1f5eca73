"""The fuzzer's runner (``gear-rattle fuzz``; docs/reference/golden_commands.md, "Fuzzing an implementation"): the search loop
that composes the draws (:mod:`.scenarios`: scenarios and the inputs built from them), the implementation's
runs (:mod:`.process`), the scorer (:mod:`..scoring.cases`), the shrinker (:mod:`.shrinker`) and the triage
(:mod:`.triage`).

1. Inputs are drawn in batches (``--batch``) and built into certified cases (:func:`..oracle.ondemand.build_user_case`).
2. The implementation runs on a batch (:meth:`Runner.run`: one process, ``COMMAND CASES_DIR OUT_DIR``) and
   each output is scored with the suite's scorer.  A run that ends badly -- a non-zero exit status, a
   signal, ``--timeout`` -- fails no case by itself: the cases whose file is right pass, the others are
   *suspects*, run again in halves until each failure is pinned on one case run alone
   (:meth:`Runner.evaluate`, a bisection); a crash, a timeout, a missing or malformed file of one input is
   then a failure of that input like a wrong value.
3. Each failure gets its :class:`.triage.Signature`; a new signature is a new group, written at once, shrunk to the simplest input that fails the same way, run alone once more so
   that its kept output, stdout, stderr and exit status are its own, and written again; a failure of a
   known group is counted.  The run stops after the first group unless ``keep_going``.
"""

from __future__ import annotations

import contextlib
import json
import shlex
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ...extras import require
from ..formats.cases import Case, load_case, read_sequence
from ..formats.textformat import MalformedFile, MissingFile
from ..oracle.ondemand import CaseError, UserCase, build_user_case, write_user_case
from ..scoring.cases import score_sequence
from .process import ImplementationError, RunStatus, WorkFolder, output_bytes
from .reaper import remove_tree
from .scenarios import SCENARIOS, construct, draw_recipes
from .shrinker import shrink
from .triage import Group, GroupWriter, Signature, group_id, score_signature, store_plain

#: Cases per batch (one process of the implementation each), seconds a batch may take by default.
BATCH, TIMEOUT = 24, 300.0
#: Seconds the shrinking of one failure may take (it usually stops earlier: no simpler candidate fails);
#: at most the budget.
SHRINK_TIME = 90.0
#: The least time a shrunk case's run alone may take (seconds; at most ``--timeout``), even when the
#: shrinking spent its time.
ALONE_MIN_S = 10.0


def split_command(command: str) -> list[str]:
    """``COMMAND`` as an argument list (shell words); ``ValueError`` when empty or unbalanced."""
    try:
        words = shlex.split(command)
    except ValueError as e:
        raise ValueError(f"--impl {command!r}: {e}") from None
    if not words:
        raise ValueError("--impl is empty: allowed a command, called as COMMAND CASES_DIR OUT_DIR")
    return words


# ---------------------------------------------------------------------------------------------
# one case in one run


@dataclass
class Outcome:
    """What one run said about one case: ``signature`` None when it passes; ``message`` one line naming
    the output file at ``output_path`` (a temporary file: the triage names the kept copy); ``output`` its
    bytes (None where there was no regular file); ``suspect``: it failed in a run that failed as a whole
    (to be run again); ``unresolved``: why it could not be decided (the fuzzer's time ran out)."""

    case: UserCase
    signature: Signature | None
    message: str
    status: RunStatus
    score: object = None
    output: bytes | None = None
    output_path: str = ""
    suspect: bool = False
    unresolved: str = ""


def _one_line(text: object, limit: int = 400) -> str:
    return " ".join(str(text).split())[:limit]


def _last_line(data: bytes) -> str:
    lines = data.decode("utf-8", "replace").strip().splitlines()
    return _one_line(lines[-1], 300) if lines else ""


def read_output(case: UserCase, ref: Case, out: Path, status: RunStatus) -> Outcome:
    """Score the implementation's file ``out/<id>.csv`` against the reference case ``ref``; the one
    place the fuzzer reads an implementation's output (regular files only, bounded:
    :func:`.process.output_bytes`; then the suite's strict reader)."""
    id_ = case.input.id
    path = out / f"{id_}.csv"
    o = Outcome(case, None, "", status, output_path=str(path))
    try:
        o.output = output_bytes(path)
        got = read_sequence(path)
    except MissingFile:
        o.signature, o.message = (
            Signature("missing output"),
            "no output: the implementation wrote no file for this case",
        )
    except MalformedFile as e:
        o.signature, o.message = Signature("malformed"), f"malformed output: {_one_line(e)}"
    else:
        o.score = score_sequence(ref, got)
        if not o.score.passed:
            o.signature, o.message = score_signature(o.score, got, ref.expected), o.score.message
    o = _judged(o)
    if o.signature is None and not o.suspect:
        o.output = None  # kept only for failures (a batch may hold many files)
    return o


def _judged(o: Outcome) -> Outcome:
    """The outcome given how its run ended: a right file is right whatever the run did in a batch; in a
    run that failed as a whole, a failing case is a suspect; a case run alone fails with the run (a crash
    or a timeout); a run stopped by the fuzzer's deadline decides nothing it did not write right."""
    st = o.status
    if st.ok or (o.signature is None and st.cases > 1):
        return o
    if st.cut:
        o.signature, o.unresolved = None, f"the implementation {st.describe()}"
    elif st.cases > 1:
        o.suspect = True
    else:
        rc = st.returncode
        detail = None if rc is None else (f"exit {rc}" if rc >= 0 else st.as_dict()["signal"])
        file_said = o.message if o.signature is not None and o.signature.kind != "missing output" else ""
        o.signature = Signature("timeout") if st.timed_out else Signature("crash", detail=detail)
        last = _last_line(st.stderr) or _last_line(st.stdout)
        o.message = f"the implementation {st.describe()} on this case alone" + (f": {last}" if last else "")
        o.message += f" (its output: {file_said})" if file_said else ""
    return o


# ---------------------------------------------------------------------------------------------
# runs and isolation


@dataclass
class Runner:
    """Runs the implementation ``command`` on cases in the work folder ``work`` (``--timeout`` per run)."""

    command: list[str]
    work: WorkFolder
    timeout: float
    runs: int = 0

    def run(self, cases: list[UserCase], limit: float | None = None) -> dict:
        """One run on ``cases`` (their settings only), at most ``limit`` seconds besides ``--timeout``;
        ``{id: Outcome}``."""
        if limit is not None and limit <= 0:  # the deadline has passed: nothing is run
            st = RunStatus(None, cut=True, cases=len(cases), timeout=self.timeout)
            why = "not run: the fuzzer's time (--budget) was spent"
            return {c.input.id: Outcome(c, None, "", st, unresolved=why) for c in cases}
        self.runs += 1
        folder = self.work.path / f"r{self.runs}"
        given, ref, out = folder / "cases", folder / "reference", folder / "out"
        try:
            out.mkdir(parents=True)
            refs = {}
            for c in cases:
                (given / c.input.id).mkdir(parents=True)
                (given / c.input.id / "settings.json").write_text(json.dumps(c.settings, indent=1) + "\n")
                refs[c.input.id] = load_case(write_user_case(ref, c))  # read before the run
            status = self.work.run(self.command, given, out, self.timeout, limit)
            status.cases = len(cases)
            outs = {c.input.id: read_output(c, refs[c.input.id], out, status) for c in cases}
        finally:
            remove_tree(folder)
        if not status.ok and not status.cut and len(cases) > 1 and not any(o.suspect for o in outs.values()):
            for o in outs.values():  # every file right, yet the run failed: each case is a suspect
                o.suspect = True
        return outs

    def evaluate(self, cases: list[UserCase], deadline: float | None = None, isolate_s: float = SHRINK_TIME) -> dict:
        """``{id: Outcome}`` of ``cases``, every failure of a run pinned on one case (module docstring).
        ``deadline``: no run goes past it (None: the first run has ``--timeout``, the isolation
        ``isolate_s`` seconds more); what is not decided by then is ``unresolved``."""
        outs = self.run(cases, None if deadline is None else deadline - time.monotonic())
        if deadline is None:
            deadline = time.monotonic() + isolate_s
        return self._resolve(cases, outs, deadline)

    def _resolve(self, cases: list[UserCase], outs: dict, deadline: float) -> dict:
        if not any(o.suspect for o in outs.values()):
            return outs
        res = {i: o for i, o in outs.items() if not o.suspect}
        rest = [c for c in cases if outs[c.input.id].suspect]
        parts = [rest] if len(rest) < len(cases) else [rest[: len(rest) // 2], rest[len(rest) // 2 :]]
        for part in parts:
            left = deadline - time.monotonic()
            if left <= 0:
                for c in part:
                    o = outs[c.input.id]
                    o.signature, o.suspect = None, False
                    o.unresolved = f"not isolated: a run of {len(cases)} cases {o.status.describe()}"
                    res[c.input.id] = o
                continue
            res.update(self._resolve(part, self.run(part, left), deadline))
        return res


# ---------------------------------------------------------------------------------------------
# the search


@contextlib.contextmanager
def hypothesis_home(path: Path):
    """Hypothesis's files (its cache of the constants of local source files; the draws keep no example
    database) under ``path`` for the block, instead of ``./.hypothesis`` in the current directory (its
    default); the earlier setting is restored after."""
    configuration = require("hypothesis", "test", "gear-rattle fuzz (the draws)").configuration
    before = vars(configuration).get("__hypothesis_home_directory")
    configuration.set_hypothesis_home_dir(path)
    try:
        yield
    finally:
        configuration.set_hypothesis_home_dir(before)


@dataclass
class FuzzResult:
    """What a run found: ``groups`` (:class:`.triage.Group`, each written), the cases run, the
    implementation's runs (``batches``), inputs drawn and skipped, failing inputs (``failed_inputs``; those
    of the last batch left without a group when the run stops at the first: ``untriaged``), inputs that
    could not be decided in time (``unresolved``), scenarios drawn, and an ``error`` that stopped it."""

    groups: list = field(default_factory=list)
    cases: int = 0
    batches: int = 0
    drawn: int = 0
    skipped: int = 0
    failed_inputs: int = 0
    untriaged: int = 0
    unresolved: int = 0
    scenarios: dict = field(default_factory=dict)
    elapsed: float = 0.0
    error: str = ""

    @property
    def unwritten(self) -> list[str]:
        """One line per file that could not be written."""
        return [u for g in self.groups for u in g.unwritten]


def _member(c: UserCase) -> dict:
    return {"id": c.input.id, "input": c.input.as_dict()}


@dataclass
class _Search:
    """The loop's state: the result, the runner, the writer (None: nothing written) and the groups."""

    res: FuzzResult
    runner: Runner
    writer: GroupWriter | None
    seed: int
    budget: float
    keep_going: bool
    t0: float
    progress: Callable | None = None
    groups: dict = field(default_factory=dict)

    def batches(self, batch: int, allowed: list[str], deadline: float):
        """Batches of ``(case, scenario)`` drawn until the deadline (recipe ``k`` of round ``r`` from the seed
        ``(seed * 100_003 + r, k)``: reproducible)."""
        res, round_ = self.res, 0
        while time.monotonic() < deadline:
            recipes = draw_recipes(self.seed * 100_003 + round_, batch, allowed)
            round_ += 1
            cases: list[tuple[UserCase, str]] = []
            for rec in recipes:
                if len(cases) >= batch or time.monotonic() >= deadline:
                    break
                res.drawn += 1
                inp = construct(rec, f"fuzz-{self.seed}-{res.drawn:06d}")
                try:
                    if inp is None:
                        raise CaseError("no input")
                    cases.append((build_user_case(inp), rec["scenario"]))
                except CaseError:
                    res.skipped += 1
                    continue
                res.scenarios[rec["scenario"]] = res.scenarios.get(rec["scenario"], 0) + 1
            if cases:
                yield cases

    def triage(self, cases: list[tuple[UserCase, str]], outcomes: dict) -> None:
        """Count, group, write and shrink the failures of a batch."""
        grown = []
        for c, scenario in cases:
            o = outcomes[c.input.id]
            self.res.unresolved += bool(o.unresolved)
            if o.signature is None:
                continue
            self.res.failed_inputs += 1
            g = self.groups.get(o.signature)
            if g is not None:
                g.count += 1
                g.members.append(_member(c))
                g.scenarios[scenario] = g.scenarios.get(scenario, 0) + 1
                grown.append(g)
            elif self.res.groups and not self.keep_going:
                self.res.untriaged += 1
            else:
                self.new_group(c, scenario, o)
        for g in {id(g): g for g in grown}.values():
            if self.writer is not None:
                self.writer.update(g)

    def new_group(self, c: UserCase, scenario: str, o: Outcome) -> None:
        """A new group: written as found, shrunk, run alone, written again."""
        k = len(self.res.groups) + 1
        g = Group(
            group_id(self.seed, k, o.signature),  # type: ignore[arg-type]
            o.signature,  # type: ignore[arg-type]
            scenario,
            c,
            o,
            c.input,
            time.monotonic() - self.t0,
            members=[_member(c)],
            scenarios={scenario: 1},
            alone=o.status.cases == 1,
        )
        self.groups[o.signature] = g
        self.res.groups.append(g)
        if self.writer is not None:
            self.writer.write(g)  # before anything else can fail: the failure as found
        if self.progress is not None:  # shrinking takes up to SHRINK_TIME: say so, not a count that stands still
            self.progress(self.res.cases, len(self.res.groups), f"shrinking {o.signature.text()}")  # type: ignore[union-attr]
        deadline = time.monotonic() + min(self.budget, SHRINK_TIME)
        case, best, rounds = shrink(c, o, lambda cs: self.runner.evaluate(cs, deadline), deadline)
        if rounds:
            g.case, g.outcome, g.shrink_rounds, g.shrunk = case, best, rounds, True
        g.alone = g.outcome.status.cases == 1
        if not g.alone:
            self.alone(g, deadline)
        if self.writer is not None:
            self.writer.write(g)  # replaces the first one

    def alone(self, g: Group, deadline: float) -> None:
        """Run the group's case alone: its kept files are then its own (else a note says why not)."""
        o = self.runner.run([g.case], max(ALONE_MIN_S, deadline - time.monotonic()))[g.case.input.id]
        if o.signature == g.signature:
            g.outcome, g.alone = o, True
            return
        got = o.unresolved or ("it passed" if o.signature is None else f"it failed otherwise: {o.signature.text()}")
        g.note = f"run alone, the case does not fail the same way ({got}): the kept files are those of its batch"


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
    store: Callable[[dict], None] = store_plain,
    hypothesis_dir: Path | None = None,
    work_root: Path | None = None,
) -> FuzzResult:
    """Fuzz the implementation ``command`` for ``budget`` seconds (module docstring); each group is written
    under ``out`` (None: nothing written) through ``store`` (``{path: bytes}``, all or none: the command
    line passes its atomic writer), with an ``index.json``.  ``progress(cases, groups, doing=None)`` after each
    batch, and with ``doing`` (what takes the time: ``shrinking <signature>``) before each group is shrunk.
    Hypothesis keeps its files in ``hypothesis_dir`` (default: the run's work folder, removed at the end);
    the work folder is made in ``work_root`` (default: the temporary directory).  An implementation that
    cannot be started ends the run: ``result.error``."""
    require("hypothesis", "test", "gear-rattle fuzz (the draws)")
    t0 = time.monotonic()
    res = FuzzResult()
    writer = GroupWriter(out, seed, shlex.join(command), store) if out is not None else None
    with WorkFolder(work_root) as work, hypothesis_home(hypothesis_dir or work.path / "hypothesis"):
        runner = Runner(command, work, timeout)
        search = _Search(res, runner, writer, seed, budget, keep_going, t0, progress)
        try:
            for cases in search.batches(batch, scenarios or list(SCENARIOS), t0 + budget):
                outcomes = runner.evaluate([c for c, _ in cases], None, min(budget, SHRINK_TIME))
                res.cases += len(cases)
                search.triage(cases, outcomes)  # new groups are shrunk here (progress says so)
                if progress is not None:
                    progress(res.cases, len(res.groups))
                if res.groups and not keep_going:
                    break
        except ImplementationError as e:
            res.error = str(e)
        finally:
            res.batches = runner.runs
    res.elapsed = time.monotonic() - t0
    return res


def summary(res: FuzzResult, **head) -> dict:
    """The JSON summary of a run (stdout and ``--json``): ``head`` (the implementation, seed, budget ...),
    the counts, one entry per group (:meth:`.triage.Group.summary`), what could not be written, the status."""
    return {
        **head,
        "elapsed_s": round(res.elapsed, 2),
        "cases": res.cases,
        "batches": res.batches,
        "inputs_drawn": res.drawn,
        "inputs_skipped": res.skipped,
        "scenarios": res.scenarios,
        "failed_inputs": res.failed_inputs,
        "untriaged_inputs": res.untriaged,
        "unresolved_inputs": res.unresolved,
        "groups": [g.summary() for g in res.groups],
        "unwritten": res.unwritten,
        "status": "error" if res.error else ("failures" if res.groups else "clean"),
        "error": res.error or None,
    }
