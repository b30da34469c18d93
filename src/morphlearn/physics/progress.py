"""Progress lines for long work in rule logs."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO


class EpisodeProgress:
    """Episode-level progress lines for a shard log: one line at most every ``every_s`` seconds
    and one at the end of the design (a paper-resolution empirical design runs 58,564 episodes,
    hours of one core, so a per-design line alone would leave the log silent for hours).
    ``at_most``: the adaptive weight grid simulates an unknown share of the ``total`` episodes
    (10-60 %), so the count is an upper bound and so is the time left it gives (the rest at the
    rate so far, as if every episode were simulated); :class:`DesignsProgress` gives the shard's
    time left from the designs done. ``stream``: where the lines go (``morphlearn design``: stderr,
    so that its --json stays one line)."""

    def __init__(
        self,
        label: str,
        every_s: float = 30.0,
        clock: Callable[[], float] = time.monotonic,
        at_most: bool = False,
        stream: TextIO | None = None,
    ) -> None:
        self.label, self.every_s, self.clock, self.at_most = label, every_s, clock, at_most
        self.stream = stream
        self.start = self.last = clock()

    def _say(self, text: str) -> None:
        print(text, file=self.stream or sys.stdout, flush=True)

    def __call__(self, done: int, total: int) -> None:
        now = self.clock()
        if now - self.last < self.every_s and done < total:
            return
        self.last = now
        took = now - self.start
        if self.at_most:
            if done >= total:
                self._say(f"{self.label}: done in {took:.0f} s (adaptive weight grid)")
            else:
                bound = took / max(done, 1) * (total - done)
                self._say(
                    f"{self.label}: {done}/{total} episodes at most (adaptive weight grid), {took:.0f} s so far, "
                    f"at most ~{bound:.0f} s left in this design"
                )
            return
        rate = took / done
        left = f", ~{rate * (total - done):.0f} s left in this design" if done < total else ""
        self._say(f"{self.label}: {done}/{total} episodes, {rate:.3f} s each{left}")


class DesignsProgress:
    """A shard's time left, from the designs it has finished: one line after each design (the
    mean time of those done times the designs left; designs differ, 114-234 CPU-s each in the ODE
    survey, so the estimate firms up as designs finish)."""

    def __init__(self, total: int, clock: Callable[[], float] = time.monotonic, stream: TextIO | None = None) -> None:
        self.total, self.clock, self.stream = total, clock, stream
        self.start = clock()

    def __call__(self, done: int) -> str:
        took = self.clock() - self.start
        left = took / done * (self.total - done) if done else float("nan")
        text = f"designs {done}/{self.total} done in {took:.0f} s" + (
            f", ~{left:.0f} s left in this shard (at the mean of the designs done)" if done < self.total else ""
        )
        print(text, file=self.stream or sys.stdout, flush=True)
        return text
