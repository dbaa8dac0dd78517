"""``python -m mimo_ta``: run a packaged test article, or find the ``mimo`` binary.

    python -m mimo_ta simple          # the simple EKF + nearest-neighbour test article (stdin/stdout protocol)
    python -m mimo_ta which           # the mimo binary helpers use (mimo_ta.binary)

A test article is meant to be started by ``mimo``:
``mimo simulate --scenario 1 --ta-cmd "python -m mimo_ta simple"``.
"""

from __future__ import annotations

import argparse
import sys


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m mimo_ta", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    sub.add_parser("simple", help="run the simple test article (mimo_ta.simple) on stdin/stdout")
    sub.add_parser("which", help="print the path of the mimo binary")
    a = ap.parse_args(argv)
    if a.command == "simple":
        from .simple import SimpleTa

        return SimpleTa().run()
    from .binary import find_mimo_bin

    try:
        print(find_mimo_bin())
    except FileNotFoundError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
