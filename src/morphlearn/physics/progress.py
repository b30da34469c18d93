"""Progress lines for long work in rule logs."""

from __future__ import annotations

import time
from collections.abc import Callable


class EpisodeProgress:
    """Episode-level progress lines for a shard log: one line at most every ``every_s`` seconds
    and one at the end of the design (a paper-resolution empirical design runs 58,564 episodes,
    hours of one core, so a per-design line alone would leave the log silent for hours).
    ``at_most``: the adaptive weight grid simulates an unknown share of the ``total`` episodes
    (10-60 %), so the count is said to be an upper bound and no time left is guessed."""

    def __init__(
        self, label: str, every_s: float = 30.0, clock: Callable[[], float] = time.monotonic, at_most: bool = False
    ) -> None:
        self.label, self.every_s, self.clock, self.at_most = label, every_s, clock, at_most
        self.start = self.last = clock()

    def __call__(self, done: int, total: int) -> None:
        now = self.clock()
        if now - self.last < self.every_s and done < total:
            return
        self.last = now
        if self.at_most:
            if done >= total:
                print(f"{self.label}: done in {now - self.start:.0f} s (adaptive weight grid)", flush=True)
            else:
                print(f"{self.label}: {done}/{total} episodes at most (adaptive weight grid)", flush=True)
            return
        rate = (now - self.start) / done
        left = f", ~{rate * (total - done):.0f} s left in this design" if done < total else ""
        print(f"{self.label}: {done}/{total} episodes, {rate:.3f} s each{left}", flush=True)
