"""The model interface: what every model plug-in implements (the registry: :mod:`morphlearn.models`).

A model is a plug-in (:class:`Model`): its name, its config section parsed into its own settings,
the designs it simulates and their shards, its weights, its science record, how it handles mirror
images, how it evaluates a batch of designs, the backend and device it records, and its rule's
resources. The workflow's simulate / merge / metrics rules are written once and instantiated per
registered model; summary, compare, bundle, provenance, captions, the reproduction table and the
CLI ask the registry instead of comparing names.

To add a model: its own package with a :class:`Model` subclass, one line in
``morphlearn.models.MODELS``, and its config section in ``config_schema.yaml``.

Light imports only: the Snakefile imports this module at parse time.
"""

from __future__ import annotations

import argparse
import copy
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from morphlearn.grid import split_shards

if TYPE_CHECKING:
    from morphlearn.metrics import Thresholds
    from morphlearn.results import DesignResult
    from morphlearn.settings import Settings, Shared

#: Called as each design of a batch finishes: (index in the batch, its result).
Done = Callable[[int, "DesignResult"], None]
#: Where a design (a flat index) keeps its finished episodes while it runs: the design cache's
#: partial file (:func:`morphlearn.physics.design_cache.partial_path`), which owns and removes it.
PartialPath = Callable[[int], Path]


@dataclass(frozen=True)
class Resources:
    """What a model's shard rule asks of the scheduler."""

    threads: int
    runtime: int  # minutes
    mem_mb: int
    gpu: int = 0


class Model(ABC):
    """The interface every model implements (see the module docstring)."""

    #: Registry key, config section, results folder name and the ``model`` of its records.
    name: ClassVar[str]
    #: The per-rule environment of its shard rule (``envs/``), for ``--sdm conda``.
    env_file: ClassVar[str]
    #: Options of ``morphlearn design`` this model takes (others are refused, by name).
    cli_options: ClassVar[tuple[str, ...]] = ()
    #: Python libraries its results depend on, whose versions its provenance records name.
    libraries: ClassVar[tuple[str, ...]] = ()
    #: Config keys of its section that name files Snakemake reads or writes (checked at start).
    path_keys: ClassVar[tuple[str, ...]] = ()
    #: The config section whose schema its section shares when ``config_schema.yaml`` has none of
    #: its own (a new engine on the physics base needs no schema entry), or None.
    schema_like: ClassVar[str | None] = None

    # -- settings (parsed once, at the edge) ---------------------------------------------------
    @abstractmethod
    def parse(self, section: Mapping[str, Any], shared: Shared) -> Any:
        """This model's section of the validated config (``section``: the mapping under its name,
        defaults filled), typed, with the typed sections it may also need (``shared``: grid,
        sweep, figures); files it names read once. Raises ConfigError naming the key."""

    def settings(self, s: Settings) -> Any:
        return s.models[self.name]

    def enabled(self, s: Settings) -> bool:
        return bool(self.settings(s).enabled)

    def results_from(self, s: Settings) -> str | None:
        """A bundle its results are read from instead of simulated (None: simulate)."""
        return None

    def simulates(self, s: Settings) -> bool:
        return self.enabled(s) and self.results_from(s) is None

    # -- the sweep ---------------------------------------------------------------------------------
    def inputs(self, s: Settings) -> dict[str, str]:
        """Files its shard rule reads (editing one re-runs the shards), by name."""
        return {}

    @abstractmethod
    def designs(self, s: Settings) -> np.ndarray:
        """Sorted design indices this model simulates (mirror images it derives left out)."""

    def shard_designs(self, s: Settings) -> list[np.ndarray]:
        return split_shards(self.designs(s), self.settings(s).shards)

    def weights(self, s: Settings) -> np.ndarray:
        return s.weights(self.name)

    def science(self, s: Settings) -> dict[str, Any]:
        """The config subset that determines its numbers (its digest keys caches and stores): a
        copy of the record its parse made (its settings' ``science``; empty when it simulates
        nothing)."""
        return copy.deepcopy(dict(self.settings(s).science or {}))

    @abstractmethod
    def mirror_derived(self, s: Settings) -> bool:
        """Whether the merge derives the mirror images of the simulated designs."""

    @abstractmethod
    def thresholds(self, s: Settings) -> Thresholds:
        """Success thresholds its metrics apply to the stored arrays."""

    @abstractmethod
    def evaluate(
        self, s: Settings, designs: np.ndarray, done: Done | None = None, partial: PartialPath | None = None
    ) -> list[DesignResult]:
        """Results of ``designs`` (flat indices), in order; ``done`` as each one finishes.
        ``partial``: where a design may keep its finished episodes while it runs, to resume inside
        itself (a model whose designs are short units ignores it); None: nowhere."""

    @abstractmethod
    def backend(self, s: Settings) -> dict[str, str]:
        """The backend and device that make its shards (recorded, compared at the merge)."""

    @abstractmethod
    def resources(self, s: Settings) -> Resources: ...

    def resimulate(self, science: Mapping[str, Any], designs: np.ndarray) -> list[DesignResult]:
        """Results of ``designs`` re-made from a science record (a bundle's store), the way the run
        that recorded it made them, its levers included (``morphlearn check-bundle --resimulate``).
        A model that cannot re-make its results from its record raises NotImplementedError."""
        raise NotImplementedError(f"model {self.name!r} cannot re-simulate from its science record")

    # -- reading its records -----------------------------------------------------------------------
    @abstractmethod
    def positions_of(self, science: Mapping[str, Any]) -> int:
        """Positions per axis of the grid a science record was made on."""

    @abstractmethod
    def describe(self, science: Mapping[str, Any], n_designs: int, m: int) -> str:
        """One sentence for captions: the settings a dataset was made with (from its record)."""

    def not_the_paper(self, science: Mapping[str, Any]) -> str:
        """Why results made with ``science`` cannot answer the paper's claims as the paper put them
        (another robot or another engine: a clause for the reproduction table), or "" when they can
        (the theory; the paper's robot in the paper's engine). The weight and design grids are the
        table's to check, not this."""
        return ""

    # -- the command line (``morphlearn design``) ---------------------------------------------------
    def check_cli(self, a: argparse.Namespace) -> None:
        """Refuse physically meaningless options (raise ``cli.UsageError``); the config's rule where
        the model has one. By default nothing beyond the CLI's range checks."""
        return None

    @abstractmethod
    def evaluate_one(
        self, l1: tuple[float, float], l2: tuple[float, float], w: np.ndarray, a: argparse.Namespace
    ) -> DesignResult:
        """One design's results for the CLI, from its options (already range-checked)."""
