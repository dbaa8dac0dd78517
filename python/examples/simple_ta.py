#!/usr/bin/env python3
"""The simple test article (``mimo_ta/simple.py``: EKF + nearest neighbour, monostatic and MIMO
dwells), runnable in place from a checkout — the template to start from.

    mimo simulate --scenario 1 --ta-cmd "python3 python/examples/simple_ta.py" --out runs/s1-py

Installed (``pip install .`` or ``pip install ./python``), the same test article is
``python3 -m mimo_ta simple``.
"""

import sys
from pathlib import Path

# Use the package of this checkout when run from the repository (else the installed one).
_REPO_PYTHON = Path(__file__).resolve().parents[1]
if (_REPO_PYTHON / "mimo_ta").is_dir():
    sys.path.insert(0, str(_REPO_PYTHON))

from mimo_ta.simple import DEFAULTS, SimpleTa, Track  # noqa: E402,F401

if __name__ == "__main__":
    sys.exit(SimpleTa().run())
