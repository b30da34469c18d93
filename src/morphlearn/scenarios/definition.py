"""The scenario file and what it makes: names, allowed overrides, and each scenario's settings
(the base config with its overrides, validated with the same schema)."""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from morphlearn import config as cfgmod
from morphlearn import configure, models
from morphlearn.settings import Settings

#: The reference scenario every comparison is made against; every scenario file must define it.
BASE = "base"
#: Scenario names: folder names, not starting with '_' (reserved for shared simulations).
NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
#: Top-level config keys a scenario may override (the theory sweep and its analysis).
OVERRIDABLE = ("grid", "theory", "sweep", "analysis", "design_cache")


class ScenarioError(cfgmod.ConfigError):
    """A bad scenario file, name or override (one line, naming it)."""


@dataclass(frozen=True)
class Scenario:
    name: str
    overrides: dict[str, Any]
    settings: Settings  # the scenario "as if simulated"

    @property
    def theory(self) -> Any:
        """Its theory parameters (morphlearn.theory.TheoryParams)."""
        return self.settings.models["theory"].params

    @property
    def horizon(self) -> float:
        return float(self.theory.horizon)

    @property
    def radius(self) -> float:
        return float(self.theory.success_radius)


def read_file(path: str | Path) -> dict[str, dict[str, Any]]:
    """Scenario name -> overrides, checked for form (names, allowed keys); not yet validated."""
    data = cfgmod._read_yaml(path)
    out: dict[str, dict[str, Any]] = {}
    for name, over in data.items():
        if not isinstance(name, str) or not NAME_RE.match(name):
            raise ScenarioError(
                f"{path}: scenario name {name!r} is invalid; allowed: letters, digits, "
                "'_', '.', '-', not starting with '_' or '.'"
            )
        over = {} if over is None else over
        if not isinstance(over, dict):
            raise ScenarioError(
                f"{path}: scenario {name!r} must be a mapping of config overrides, got {type(over).__name__}"
            )
        bad = sorted(set(over) - set(OVERRIDABLE))
        if bad:
            raise ScenarioError(
                f"{path}: scenario {name!r}: key{'s' if len(bad) > 1 else ''} {bad} "
                f"cannot be overridden; allowed: {list(OVERRIDABLE)}"
            )
        for k in ("horizon", "success_radius"):
            if over.get("analysis", {}).get(k) is not None:
                raise ScenarioError(
                    f"{path}: scenario {name!r}: analysis.{k} is set by the planner; "
                    f"allowed: theory.{k} (derived from a stored simulation if it can be)"
                )
        out[name] = over
    if BASE not in out:
        raise ScenarioError(
            f"{path}: no scenario named {BASE!r}; allowed: a file that defines "
            f"'{BASE}' (the reference of the comparison, usually {{}})"
        )
    return out


def select(available: Iterable[str], wanted: str | Sequence[str]) -> list[str]:
    """The scenarios to run, in file order, always with the base: ``"all"``, a comma-separated
    string of names, or a list of names."""
    avail = list(available)
    names = [s.strip() for s in wanted.split(",")] if isinstance(wanted, str) else [str(s) for s in wanted]
    names = [n for n in names if n]
    if names == ["all"]:
        return avail
    unknown = [n for n in names if n not in avail]
    if unknown or not names:
        raise ScenarioError(
            f"scenarios = {wanted!r}: unknown scenario{'s' if len(unknown) > 1 else ''} "
            f"{unknown}; allowed: 'all' or names from {avail}"
        )
    chosen = {BASE, *names}
    return [n for n in avail if n in chosen]


def expand(base: Settings, file_scenarios: dict[str, dict[str, Any]], names: Sequence[str]) -> list[Scenario]:
    """Each named scenario's settings: base config + overrides, theory only, its own results
    folder ``<results_dir>/scenarios/<name>``."""
    root = scenarios_dir(base)
    out = []
    for name in names:
        over = file_scenarios[name]
        raw = cfgmod.deep_merge(dict(base.source), over)
        raw = cfgmod.deep_merge(
            raw,
            {
                "results_dir": f"{root}/{name}",
                # theory only: every other registered model off
                **{n: {"enabled": False} for n in models.MODELS if n != models.REFERENCE},
                "figures": {"enabled": False},
                "bundle_dir": None,
                "render_only": False,
                "scenarios": None,
            },
        )
        try:
            sc = configure.parse(raw)
        except cfgmod.ConfigError as e:
            raise ScenarioError(f"scenario {name!r}: {e}") from None
        if sc.analysis.horizon is not None or sc.analysis.success_radius is not None:
            raise ScenarioError(
                f"scenario {name!r}: the base config sets analysis.horizon/success_radius; "
                "allowed: null in the base config of a scenario run"
            )
        out.append(Scenario(name, over, sc))
    return out


def scenarios_dir(base: Settings) -> str:
    return f"{base.results_dir}/scenarios"
