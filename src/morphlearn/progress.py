"""Progress lines for long work in rule logs."""

from __future__ import annotations

import time
from collections.abc import Callable


class EpisodeProgress:
    """Episode-level progress lines for a shard log: one line at most every ``every_s`` seconds
    and one at the end of the design (a paper-resolution empirical design runs 58,564 episodes,
    hours of one core, so a per-design line alone would leave the log silent for hours)."""

    def __init__(self, label: str, every_s: float = 30.0, clock: Callable[[], float] = time.monotonic) -> None:
        self.label, self.every_s, self.clock = label, every_s, clock
        self.start = self.last = clock()

    def __call__(self, done: int, total: int) -> None:
        now = self.clock()
        if now - self.last < self.every_s and done < total:
            return
        self.last = now
        rate = (now - self.start) / done
        left = f", ~{rate * (total - done):.0f} s left in this design" if done < total else ""
        print(f"{self.label}: {done}/{total} episodes, {rate:.3f} s each{left}", flush=True)
