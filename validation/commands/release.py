"""``python -m gear_rattle.validation.commands.release``: the certified post-release duration
``T_post`` of the canonical release orbit from the command line (docs/release.md).

Not a ``gear-rattle`` subcommand (it is not in :func:`validation.cli.command_modules`): a
``python -m`` entry of its own with its own options, printing one summary line per wall and
parameter rounding and, with ``--json``, the full results.
"""

from __future__ import annotations

import argparse
import math
import sys

from ...mapimpl.certified.balls import MAX_PREC, CertificationError, precision
from ...core.paper import DELTA, PAPER_DECIMAL
from ...mapimpl.certified.duration import PRECISIONS, ROUNDINGS, certified_release_duration, model_params
from ...mapimpl.certified.model import PARAM_NAMES, parameter_ball
from ...mapimpl.certified.release import MAX_IMPACTS
from ...mapimpl.engine.t_post import float64_target
from ...mapimpl.float64_release import float64_release_duration


def _precisions(text: str) -> tuple:
    try:
        vals = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"--precisions={text!r}: allowed a comma-separated list of integers") from None
    if not vals or any(not 64 <= v <= MAX_PREC for v in vals) or any(b <= a for a, b in zip(vals, vals[1:])):
        raise argparse.ArgumentTypeError(
            f"--precisions={text!r} is out of range: allowed increasing integers in [64, {MAX_PREC}]"
        )
    return vals


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"{v} is out of range: allowed >= 1")
    return v


def _positive_float(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"{v} is out of range: allowed finite > 0")
    return v


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit status 2
        self.exit(2, f"{self.prog}: error: {message}\n")


def _parser() -> _Parser:
    """The command's argument parser."""
    ap = _Parser(
        prog="python -m gear_rattle.validation.commands.release",
        description="Certified post-release duration T_post of the canonical release orbit "
        "(ball arithmetic at increasing precision; docs/release.md).",
    )
    g = ap.add_argument_group("parameters (exact decimals as printed; default: the paper's Figs. 9-11)")
    for k in PARAM_NAMES:
        g.add_argument(f"--{k}", default=PAPER_DECIMAL[k], help=f"decimal (default {PAPER_DECIMAL[k]})")
    ap.add_argument("--wall", choices=("0", "-1", "both"), default="0", help="wall released from (default 0: s = 0)")
    ap.add_argument(
        "--rounding",
        choices=ROUNDINGS + ("both",),
        default="both",
        help="exact decimal parameters, their float64 roundings, or both (default)",
    )
    ap.add_argument("--delta", type=_positive_float, default=DELTA, help=f"capture distance (default {DELTA:g})")
    ap.add_argument(
        "--max-impacts",
        type=_positive_int,
        default=MAX_IMPACTS,
        help=f"most post-release impacts certified (default {MAX_IMPACTS})",
    )
    ap.add_argument(
        "--precisions",
        type=_precisions,
        default=PRECISIONS,
        help="increasing precisions in bits (default " + ",".join(map(str, PRECISIONS)) + ")",
    )
    ap.add_argument("--no-confirm", action="store_true", help="skip the confirmation at the next precision")
    ap.add_argument("--time-budget", type=_positive_float, default=None, help="seconds for each schedule")
    ap.add_argument("--float64", action="store_true", help="also run the float64 engine's own T_post")
    ap.add_argument("--json", default=None, help="write the results as JSON to this file")
    ap.add_argument("--quiet", action="store_true", help="no progress on stderr")
    return ap


def main(argv: list[str] | None = None) -> int:
    """Run the command on ``argv`` (default ``sys.argv[1:]``); returns the exit status."""
    ap = _parser()
    args = ap.parse_args(argv)
    params = {k: getattr(args, k) for k in PARAM_NAMES}
    try:
        model_params(params, "float64")
        for k in PARAM_NAMES:
            with precision(64):
                parameter_ball(k, params[k])
    except ValueError as e:
        ap.error(str(e))
    walls = (0, -1) if args.wall == "both" else (int(args.wall),)
    roundings = ROUNDINGS if args.rounding == "both" else (args.rounding,)

    from ...core.progress import Bar

    results: list[dict] = []
    float64_engine: list[dict] = []
    out = {
        "command": "python -m gear_rattle.validation.commands.release " + " ".join(argv or sys.argv[1:]),
        "results": results,
        "float64_engine": float64_engine,
    }
    try:
        # the capture target: the engine's float64 4-impact orbit (the certified track computes none)
        target = float64_target(model_params(params, "float64"))
        for wall in walls:
            for rounding in roundings:
                with Bar(f"T_post (wall {wall}, {rounding})", enabled=not args.quiet) as bar:

                    def prog(prec, n, rad, bar=bar):
                        bar.postfix(f"{prec} bits, radius {rad}")
                        bar.update(n)

                    d = certified_release_duration(
                        params,
                        wall,
                        args.delta,
                        rounding=rounding,
                        max_impacts=args.max_impacts,
                        precisions=args.precisions,
                        confirm=not args.no_confirm,
                        target=target,
                        time_budget_s=args.time_budget,
                        progress=prog,
                    )
                print(d.summary())
                for a in d.attempts:
                    print(
                        f"    {a.prec:5d} bits: {a.status:13s} impacts {a.impacts:6d}  radius {a.radius:>9s}  "
                        f"growth {a.growth:.3f} bits/impact  {a.seconds:7.1f} s  {a.reason}"
                    )
                results.append(d.to_dict())
            if args.float64:
                f = float64_release_duration(model_params(params, "float64"), wall, args.delta)
                print(f"wall {wall}, float64 engine (a sample, not a value): T_post = {f['value']} ({f['status']})")
                float64_engine.append(dict(f, wall=wall))
    except ValueError as e:
        ap.error(str(e))
    except CertificationError as e:  # pragma: no cover - two precisions disagree: a bug
        print(f"error: {e}", file=sys.stderr)
        return 1
    if args.json:
        from pathlib import Path

        from ..io import write_json

        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        write_json(args.json, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())


__all__ = [
    "main",
]
