"""MuJoCo's warnings, kept inside the run's results folder.

MuJoCo's default warning handler prints each warning (an unstable simulation: 40,131 lines for 16
episodes of 1 g wheels) and appends it to ``MUJOCO_LOG.TXT`` in the working directory, the project
folder, outside every ``results_dir``. :func:`install` (called before any model is built) replaces
that handler: each warning is counted (:data:`COUNTS`, by its text up to the first digit), said once
per kind on stderr, and appended to ``MUJOCO_LOG.TXT`` in the folder :envvar:`MORPHLEARN_LOG_DIR`
names (a workflow shard sets it to ``<results_dir>/logs/<model>``; unset: nowhere), at most
:data:`MAX_LINES` lines a process, then only counted.
"""

from __future__ import annotations

import os
import re
import sys
from collections import Counter
from pathlib import Path

#: Where the log goes: a folder (the workflow's shard sets ``<results_dir>/logs/<model>``).
LOG_DIR_ENV = "MORPHLEARN_LOG_DIR"
LOG_NAME = "MUJOCO_LOG.TXT"
#: Lines written to the log a process at most (a few unstable designs wrote 3 MB).
MAX_LINES = 1000
#: Warnings this process, by kind (the text before its first digit: DOF and time vary).
COUNTS: Counter[str] = Counter()
_installed = False


def _kind(msg: str) -> str:
    return re.split(r"\d", msg, maxsplit=1)[0].strip().rstrip(" .,:") or msg.strip()


def log_path() -> Path | None:
    d = os.environ.get(LOG_DIR_ENV)
    return Path(d) / LOG_NAME if d else None


def _warn(msg: str) -> None:
    kind = _kind(msg)
    COUNTS[kind] += 1
    path = log_path()
    if COUNTS[kind] == 1:
        where = f"; each kept in {path}" if path else ""
        print(f"MuJoCo warning: {msg.strip()} (further ones counted{where})", file=sys.stderr)
    if path is not None and sum(COUNTS.values()) <= MAX_LINES:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            with path.open("a") as f:
                f.write(f"WARNING: {msg.strip()}\n")
        except OSError:  # a log that cannot be written must not stop the simulation
            pass


def install() -> None:
    """Replace MuJoCo's warning handler (idempotent): nothing is written to the working directory."""
    global _installed
    if _installed:
        return
    import mujoco

    mujoco.set_mju_user_warning(_warn)
    _installed = True
