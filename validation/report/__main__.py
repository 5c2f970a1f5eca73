"""``python -m gear_rattle.validation.report rerender DIR``: draw a written report again from its
``document.json`` (today's verdict rules and page layout, the run's own numbers and figures; nothing
is computed).  Bad input: one line on stderr, exit status 2."""

from __future__ import annotations

import argparse
import json
import sys

from .builder import rerender


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m gear_rattle.validation.report",
        description="Draw a written validation report again from its document.json.",
    )
    ap.add_argument("action", choices=["rerender"], help="rerender: rewrite report.html, report.md, summary.json")
    ap.add_argument("dir", help="the report's folder (holds document.json and the figures)")
    a = ap.parse_args(argv)
    try:
        path = rerender(a.dir)
    except (OSError, ValueError, KeyError, TypeError, json.JSONDecodeError) as e:
        print(f"{ap.prog}: error: {e}", file=sys.stderr)
        return 2
    print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
