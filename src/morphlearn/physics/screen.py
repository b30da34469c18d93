"""The adaptive grid's screen (``<engine>.adaptive_screen: {bundle, model}``): a committed bundle
of a cheaper model's outcomes of the same designs (the reduced model's, every cell, for ODE). The
adaptive grid's first wave also simulates every cell the screen calls a success or a near miss
(:func:`morphlearn.physics.refine.screen_cells`), so the isolated single-light successes that no
lattice cell or near miss touches (they cost the ODE survey's ``at_least_one`` a controller on some
designs) are simulated where the screen finds them. The screen picks cells only: every outcome
stored is the engine's own."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from morphlearn.config import ConfigError
from morphlearn.physics.refine import screen_cells


class Screen:
    """A screen's merged store, checked against the run it screens: one line naming the key for a
    missing bundle, another grid or weight count, or a design it does not hold."""

    def __init__(self, bundle: str, model: str, key: str) -> None:
        from morphlearn import store

        path = Path(bundle) / model / "merged.zarr"
        try:
            self.ds = store.open_merged(path)
            self.science: dict[str, Any] = store.science_of(self.ds)
        except (OSError, ValueError, KeyError) as e:
            raise ConfigError(
                f"{key} = {{bundle: {bundle}, model: {model}}}: {path}: {str(e).splitlines()[0]}; "
                "allowed: a committed bundle of that model's outcomes of this run's designs"
            ) from None
        self.key, self.bundle, self.model = key, bundle, model
        self.held = {int(d): i for i, d in enumerate(self.ds["design"].values)}

    def check(self, positions: int, weights: int, designs: list[int]) -> None:
        """The screen holds these designs on this grid at these weights, or a one-line error."""
        where = f"{self.key}: {self.bundle}/{self.model}"
        if int(self.science.get("positions_per_axis", -1)) != positions:
            raise ConfigError(
                f"{where} holds the {self.science.get('positions_per_axis')}-point grid; "
                f"allowed: a screen on this run's grid ({positions} positions per axis)"
            )
        if int(self.ds.sizes["w1"]) != weights:
            raise ConfigError(
                f"{where} holds {self.ds.sizes['w1']} weights per synapse; allowed: this run's ({weights})"
            )
        lost = [d for d in designs if d not in self.held]
        if lost:
            raise ConfigError(
                f"{where} does not hold design {lost[0]} ({len(lost)} of the {len(designs)} this run "
                "simulates); allowed: a screen of every design simulated"
            )

    def cells(self, design: int, contact: float, near: float) -> np.ndarray:
        """(4, m, m) cells the screen calls a success or a near miss (within ``near`` contact
        distances, the run's own near-miss radius) for ``design``."""
        from morphlearn import store

        a = store.read_design(self.ds, self.held[int(design)])
        return screen_cells(a["first_time"], a["min_dist"], contact, near)
