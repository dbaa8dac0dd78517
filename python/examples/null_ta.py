#!/usr/bin/env python3
"""The smallest test article: it tracks nothing and asks for nothing (a benchmark of the protocol).

    mimo simulate --scenario 7 --ta-cmd "python3 python/examples/null_ta.py all" --out runs/null

The argument is the subscription's ``dwells`` (``all``, ``detections`` or ``own``, docs/ta-protocol.md
§4). It answers ``{}`` to every message without parsing it; with ``--parse`` it runs through
``mimo_ta.TestArticle`` instead, which parses every message into the package's dataclasses. On
exit it prints the number of messages to stderr.
"""

import json
import sys
from pathlib import Path

dwells = sys.argv[1] if len(sys.argv) > 1 else "detections"
start_reply = json.dumps({"name": f"null ({dwells})", "subscribe": {"dwells": dwells}}) + "\n"

if "--parse" in sys.argv:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from mimo_ta import Subscription, TestArticle

    class Null(TestArticle):
        name = f"null ({dwells}, parsed)"
        subscription = Subscription(dwells=dwells)
        messages = 0

        def handle(self, message):
            self.messages += 1
            return super().handle(message)

    ta = Null()
    ta.run()
    print(f"null TA: {ta.messages} messages", file=sys.stderr)
else:
    n = 0
    for line in sys.stdin:
        sys.stdout.write(start_reply if n == 0 else "{}\n")
        sys.stdout.flush()
        n += 1
    print(f"null TA: {n} messages", file=sys.stderr)
