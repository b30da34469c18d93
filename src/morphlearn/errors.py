"""Errors every layer may raise, and the one-line console helper the model plug-ins share.

At the bottom of the package (it imports nothing of morphlearn): a model plug-in refuses a bad
``morphlearn design`` option with :class:`UsageError` without importing the command line above it.
"""

from __future__ import annotations

import ctypes
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager


class UsageError(ValueError):
    """Bad command-line input: one line, exit code 2."""


class EngineError(RuntimeError):
    """A physics engine stopped with an error of its own (ODE's error handler, ``ode/_core.c``)
    instead of aborting the interpreter: one line naming the engine's message, exit code 1."""


@contextmanager
def c_stdout_to_stderr() -> Iterator[None]:
    """Send what C libraries print to stdout (pybullet's banner) to stderr, so ``--json`` output
    stays one JSON object."""
    sys.stdout.flush()
    saved = os.dup(1)
    os.dup2(2, 1)
    try:
        yield
    finally:
        ctypes.CDLL(None).fflush(None)  # C stdio buffers, before fd 1 is restored
        os.dup2(saved, 1)
        os.close(saved)
