"""Shared prologue of the rule scripts: log to the rule's log, thread count, the settings (the
config parsed once, here at the edge)."""

import os
import sys
from pathlib import Path
from typing import Any


def setup(smk: Any, cfg: dict | None = None) -> Any:
    """The rule's settings (``morphlearn.settings.Settings``) from the workflow's config, or from
    ``cfg`` (a scenario's simulation config, passed as a rule parameter)."""
    sys.path.insert(0, str(Path(smk.scriptdir).parents[1] / "src"))
    # Numba reads its thread count at import: set it before morphlearn imports numba.
    os.environ["NUMBA_NUM_THREADS"] = str(max(1, int(getattr(smk, "threads", 1))))
    log = open(smk.log[0], "w", buffering=1)
    sys.stderr = log
    sys.stdout = log
    from morphlearn import configure

    return configure.parse(dict(smk.config) if cfg is None else dict(cfg))
