"""How the empirical sweep runs a design's episodes: the levers that cut its cost.

- ``early_stop`` (exact; on in config.yaml): stop an episode once the reach bound
  (:mod:`.reach`) shows the light is out of reach in the time left. Successes and first-contact
  times are unchanged (validated, docs/empirical.md); a stopped episode's closest approach is
  the one up to the stop.
- ``adaptive_weights`` (an option, off by default; it can miss successes): simulate only the
  cells of the weight grid that :mod:`.refine` picks, the rest are inferred failures.
- ``adaptive_screen`` (with the adaptive grid): a committed bundle of a cheaper model's outcomes of
  the same designs (the reduced model's, for ODE); the grid's first wave also simulates every cell
  it calls a success or a near miss (:func:`.refine.screen_cells`).

Plain data (no pybullet): the config parses into it, the science record is made from it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from morphlearn.physics.reach import CHECK_EVERY
from morphlearn.physics.refine import DEFAULT_NEAR, DEFAULT_STRIDE

DEFAULT_MARGIN = 2.0


@dataclass(frozen=True)
class SweepOptions:
    early_stop: bool = False
    margin: float = DEFAULT_MARGIN
    adaptive_weights: bool = False
    stride: int = DEFAULT_STRIDE
    near: float = DEFAULT_NEAR
    #: (bundle, model) of the screen whose successes and near misses join the first wave, or None
    screen: tuple[str, str] | None = None

    @classmethod
    def from_config(cls, emp: dict[str, Any]) -> SweepOptions:
        """From the validated ``empirical`` config section."""
        return cls(
            early_stop=bool(emp.get("early_stop", False)),
            adaptive_weights=bool(emp.get("adaptive_weights", False)),
            stride=int(emp.get("adaptive_stride", DEFAULT_STRIDE)),
            near=float(emp.get("adaptive_near", DEFAULT_NEAR)),
            screen=_screen(emp.get("adaptive_screen")),
        )

    @classmethod
    def from_science(cls, sci: Mapping[str, Any]) -> SweepOptions:
        """The levers a science record says its run used (the inverse of :meth:`science`); a
        ValueError for a record this code would not reproduce (another reach-check interval)."""
        es, ad = sci.get("early_stop"), sci.get("adaptive_weights")
        try:
            out = cls(
                early_stop=bool(es),
                margin=float(es["margin"]) if es else DEFAULT_MARGIN,
                adaptive_weights=bool(ad),
                stride=int(ad["stride"]) if ad else DEFAULT_STRIDE,
                near=float(ad["near"]) if ad else DEFAULT_NEAR,
                screen=_screen(ad.get("screen")) if ad else None,
            )
        except (TypeError, KeyError, ValueError) as e:
            raise ValueError(f"levers of the science record unreadable ({type(e).__name__}: {e})") from None
        recorded = {k: sci[k] for k in ("early_stop", "adaptive_weights") if k in sci}
        if out.science() != recorded:
            raise ValueError(f"levers {recorded} recorded, this code runs {out.science()} (not reproducible here)")
        return out

    def science(self) -> dict[str, Any]:
        """The science-record entries of the levers that are on (none when all are off, so the
        digests of results made before the levers existed still hold)."""
        out: dict[str, Any] = {}
        if self.early_stop:
            out["early_stop"] = {"margin": self.margin, "check_every": CHECK_EVERY}
        if self.adaptive_weights:
            out["adaptive_weights"] = {"stride": self.stride, "near": self.near}
            if self.screen is not None:  # only when set: the digests of results made before hold
                out["adaptive_weights"]["screen"] = {"bundle": self.screen[0], "model": self.screen[1]}
        return out


def _screen(sec: Mapping[str, Any] | None) -> tuple[str, str] | None:
    return None if not sec else (str(sec["bundle"]), str(sec["model"]))
