"""Finding the ``mimo`` binary, for helpers that run it (``mimo score`` after an offline run).

The wheel built from the repository root (``pip install .``) installs ``mimo`` into the
environment's scripts directory next to ``python``; a cargo build puts it wherever
``cargo install`` or the user's PATH says. :func:`find_mimo_bin` looks where uv's Python shim
(``uv.find_uv_bin``) looks for its binary: the scripts directory of this environment
(``sysconfig.get_path("scripts")``), then the user scheme's (``pip install --user``), then
the PATH.
"""

from __future__ import annotations

import os
import shutil
import sys
import sysconfig


def _user_scheme() -> str:
    if sys.version_info >= (3, 10):
        return sysconfig.get_preferred_scheme("user")
    return "nt_user" if os.name == "nt" else "posix_user"


def find_mimo_bin() -> str:
    """The path of the ``mimo`` executable; ``FileNotFoundError`` if there is none."""
    exe = "mimo" + (sysconfig.get_config_var("EXE") or "")
    dirs = [sysconfig.get_path("scripts")]
    try:
        dirs.append(sysconfig.get_path("scripts", scheme=_user_scheme()))
    except KeyError:  # no user scheme on this platform
        pass
    for d in dirs:
        path = os.path.join(d, exe) if d else None
        if path and os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    found = shutil.which(exe)
    if found:
        return found
    raise FileNotFoundError(f"no {exe} in {', '.join(d for d in dirs if d)} nor on the PATH: install the wheel "
                            "(pip install . from the repository) or build it (cargo build -p mimo-cli)")
