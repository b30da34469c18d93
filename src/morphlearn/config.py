"""Configuration: schema validation with one-line errors, defaults, hashing of science subsets."""

from __future__ import annotations

import copy
import hashlib
import json
import math
from dataclasses import asdict, dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import jsonschema
import yaml


class ConfigError(ValueError):
    """A bad configuration value; the message names the key and what is allowed."""


def schema() -> dict[str, Any]:
    text = resources.files("morphlearn").joinpath("config_schema.yaml").read_text()
    return yaml.safe_load(text)


def _path(err: jsonschema.ValidationError) -> str:
    return ".".join(str(p) for p in err.absolute_path) or "<top level>"


def _describe(err: jsonschema.ValidationError) -> str:
    key = _path(err)
    v = err.validator
    s = err.schema
    if v == "additionalProperties":
        allowed = sorted(err.schema.get("properties", {}))
        extra = sorted(set(err.instance) - set(allowed))
        where = "" if key == "<top level>" else f" under '{key}'"
        return f"unknown key{'s' if len(extra) > 1 else ''} {extra}{where}; allowed: {allowed}"
    if v == "required":
        return f"{err.message} (in '{key}')"
    bounds = []
    if "minimum" in s:
        bounds.append(f">= {s['minimum']}")
    if "exclusiveMinimum" in s:
        bounds.append(f"> {s['exclusiveMinimum']}")
    if "maximum" in s:
        bounds.append(f"<= {s['maximum']}")
    if "enum" in s:
        bounds.append(f"one of {s['enum']}")
    allowed = f"; allowed: {s.get('type', '')} {' and '.join(bounds)}".rstrip()
    return f"{key} = {err.instance!r} is invalid ({err.message}){allowed}"


def _fill_defaults(cfg: dict[str, Any], sch: dict[str, Any]) -> None:
    for k, sub in sch.get("properties", {}).items():
        if k not in cfg and "default" in sub:
            cfg[k] = copy.deepcopy(sub["default"])
        if isinstance(cfg.get(k), dict) and sub.get("type") == "object":
            _fill_defaults(cfg[k], sub)


def validate(cfg: dict[str, Any]) -> dict[str, Any]:
    """Validate a config mapping; return a copy with defaults filled. Raises ConfigError."""
    if not isinstance(cfg, dict):
        raise ConfigError(f"config must be a mapping, got {type(cfg).__name__}")
    _check_finite(cfg, "")
    sch = schema()
    errors = sorted(
        jsonschema.Draft202012Validator(sch).iter_errors(cfg), key=lambda e: list(e.absolute_path)
    )
    if errors:
        raise ConfigError(_describe(errors[0]))
    out = copy.deepcopy(cfg)
    _fill_defaults(out, sch)
    _check_cross(out)
    return out


def _check_finite(obj: Any, key: str) -> None:
    """NaN and infinity pass JSON-schema bounds (NaN compares False): refuse them everywhere."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            _check_finite(v, f"{key}.{k}" if key else str(k))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            _check_finite(v, f"{key}.{i}")
    elif isinstance(obj, float) and not math.isfinite(obj):
        raise ConfigError(f"{key} = {obj!r} is not a finite number; allowed: finite numbers in the "
                          "range the schema gives")  # fmt: skip


def _check_results_dir(rd: str) -> None:
    p = Path(rd)
    if p.resolve() == Path(p.resolve().anchor):
        raise ConfigError(f"results_dir = {rd!r} is the file-system root; allowed: a non-empty path "
                          "other than '/' (default 'results')")  # fmt: skip
    if p.exists() and not p.is_dir():
        raise ConfigError(f"results_dir = {rd!r} is an existing file; allowed: a folder (or a new path)")


def _check_morphology(cfg: dict[str, Any]) -> None:
    """The body file is read at start (Fig. 1 and the empirical science): refuse a bad one here."""
    from morphlearn.empirical.params import load_params

    path = cfg["empirical"].get("morphology", "config/empirical_morphology.yaml")
    try:
        load_params(path)
    except ValueError as e:
        raise ConfigError(f"empirical.morphology = {path!r}: {e}; allowed: a YAML file of body "
                          "parameters") from None  # fmt: skip


def _check_analysis(a: dict[str, Any], th: dict[str, Any]) -> None:
    if a.get("horizon") is not None and a["horizon"] > th["horizon"]:
        raise ConfigError(
            f"analysis.horizon = {a['horizon']} exceeds theory.horizon = {th['horizon']}; "
            f"allowed: <= {th['horizon']} (or raise theory.horizon and re-simulate)"
        )
    rad = a.get("success_radius")
    if rad is not None and rad < th["success_radius"]:
        raise ConfigError(
            f"analysis.success_radius = {rad} is below theory.success_radius = {th['success_radius']}; "
            f"allowed: >= {th['success_radius']} or null (or lower theory.success_radius and re-simulate)"
        )
    if rad is not None and rad > th["success_radius"] and a.get("horizon") not in (None, th["horizon"]):
        raise ConfigError(
            f"analysis.horizon = {a['horizon']} with analysis.success_radius = {rad} above the simulated "
            f"radius; allowed: null or {th['horizon']} (a larger radius is known only at the simulated horizon)"
        )
    if th["success_radius"] >= th["r"]:
        raise ConfigError(f"theory.success_radius = {th['success_radius']} is not below theory.r = "
                          f"{th['r']}; allowed: < {th['r']} (the robot would start inside the light)")  # fmt: skip
    need = math.ceil(th["horizon"] / th["dt"])
    if th["integrator"] == "rk4" and th["max_steps"] < need:  # the cap would cut every trajectory short
        raise ConfigError(f"theory.max_steps = {th['max_steps']} is below the {need} steps that theory.integrator "
                          f"= rk4 takes (horizon / dt); allowed: max_steps >= {need}, or a larger dt")  # fmt: skip


def _check_cross(cfg: dict[str, Any]) -> None:
    from morphlearn.grid import DesignGrid

    _check_results_dir(cfg["results_dir"])

    g = DesignGrid(cfg["grid"]["positions_per_axis"])
    n_eval = len(g.representatives()) if cfg["sweep"]["mirror_symmetry"] else g.size
    if cfg["sweep"]["shards"] > n_eval:
        raise ConfigError(
            f"sweep.shards = {cfg['sweep']['shards']} exceeds the {n_eval} designs evaluated; "
            f"allowed: 1..{n_eval}"
        )
    emp = cfg.get("empirical")
    if emp and emp.get("enabled"):
        _check_empirical(cfg, g)
    lr = cfg["learners"]
    if lr["enabled"]:
        n_run = min(len(g.representatives()), lr["max_designs"] or g.size)
        if lr["shards"] > n_run:
            raise ConfigError(f"learners.shards = {lr['shards']} exceeds the {n_run} designs the learners "
                              f"run; allowed: 1..{n_run}")  # fmt: skip
    th = cfg["theory"]
    _check_analysis(cfg["analysis"], th)
    if (emp and emp.get("enabled")) or cfg["figures"]["enabled"]:
        _check_morphology(cfg)
    if cfg.get("render_only") and not (cfg["figures"]["enabled"] and th.get("enabled", True)):
        raise ConfigError(
            "render_only = true needs figures.enabled and theory.enabled; allowed: render_only = false "
            "or both enabled"
        )


def _check_results_from(cfg: dict[str, Any]) -> None:
    """A bundle to read the empirical results from: present, on this config's grid (its checksums
    are checked when the results are copied, by the rule empirical_from_bundle)."""
    from morphlearn import bundle

    path = cfg["empirical"]["results_from"]
    need = [Path(path) / "bundle.json", Path(path) / "empirical" / "metrics.csv",
            Path(path) / "empirical" / "merged.zarr"]  # fmt: skip
    missing = [str(p) for p in need if not p.exists()]
    if missing:
        raise ConfigError(f"empirical.results_from = {path!r}: {missing[0]} is missing; allowed: a results "
                          "bundle with empirical results (e.g. results/survey), or null to simulate")  # fmt: skip
    try:
        positions = bundle.positions_of(Path(path) / "empirical")
    except Exception as e:  # a damaged store: say which and why, in one line
        raise ConfigError(f"empirical.results_from = {path!r}: unreadable empirical results ({e})") from None
    n = cfg["grid"]["positions_per_axis"]
    if positions != n:
        raise ConfigError(f"empirical.results_from = {path!r} holds results on the {positions}-point grid; "
                          f"allowed: a bundle on grid.positions_per_axis = {n}")  # fmt: skip


def _check_empirical(cfg: dict[str, Any], g: Any) -> None:
    from morphlearn.empirical.params import EmpiricalParams

    emp = cfg["empirical"]
    if emp["results_from"] is not None:
        _check_results_from(cfg)
        return
    for k in emp.get("params", {}):
        if k not in EmpiricalParams.__dataclass_fields__:
            raise ConfigError(
                f"unknown key ['{k}'] under 'empirical.params'; "
                f"allowed: {sorted(EmpiricalParams.__dataclass_fields__)}"
            )
    try:
        EmpiricalParams.from_mapping(emp.get("params", {}))
    except ValueError as e:
        raise ConfigError(f"empirical.params.{e}") from None
    designs = emp["designs"]
    if designs != "all":
        for i, (l1, l2) in enumerate(designs):
            try:
                g.index_of(tuple(l1), tuple(l2))
            except ValueError as e:
                raise ConfigError(f"empirical.designs.{i}: {e}") from None
    if emp["mirror_derive"] and designs != "all" and not emp["include_mirrors"]:
        raise ConfigError("empirical.mirror_derive = true needs the mirror images in the results; "
                          "allowed: empirical.include_mirrors = true or empirical.designs = all")  # fmt: skip
    n = len(empirical_simulated(cfg))
    if emp["shards"] > n:
        raise ConfigError(f"empirical.shards = {emp['shards']} exceeds the {n} designs simulated; "
                          f"allowed: 1..{n}")  # fmt: skip


def empirical_simulated(cfg: dict[str, Any]) -> list[int]:
    """Sorted design indices the empirical sweep simulates: all of :func:`empirical_designs`, or
    with ``mirror_derive`` one of each mirror pair (the smaller index), the other derived."""
    designs = empirical_designs(cfg)
    if not cfg["empirical"]["mirror_derive"]:
        return designs
    from morphlearn.grid import DesignGrid

    g = DesignGrid(cfg["grid"]["positions_per_axis"])
    return sorted({min(d, int(g.mirror(d))) for d in designs})


def empirical_designs(cfg: dict[str, Any]) -> list[int]:
    """Sorted design indices the empirical results hold."""
    import numpy as np

    from morphlearn.grid import DesignGrid

    g = DesignGrid(cfg["grid"]["positions_per_axis"])
    emp = cfg["empirical"]
    if emp["designs"] == "all":
        return list(range(g.size))
    d = np.array([g.index_of(tuple(l1), tuple(l2)) for l1, l2 in emp["designs"]])
    if emp["include_mirrors"]:
        d = np.concatenate([d, g.mirror(d)])
    return sorted(set(int(x) for x in d))


def load(path: str | Path, overrides: list[str | Path] = ()) -> dict[str, Any]:
    """Load a YAML config (deep-merging override files, as ``--configfile`` does) and validate."""
    cfg = _read_yaml(path)
    for o in overrides:
        cfg = deep_merge(cfg, _read_yaml(o))
    return validate(cfg)


def _read_yaml(path: str | Path) -> dict[str, Any]:
    try:
        data = yaml.safe_load(Path(path).read_text())
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        raise ConfigError(f"{path}: malformed YAML{where}") from None
    except OSError as e:
        raise ConfigError(f"{path}: cannot read ({e.strerror})") from None
    if not isinstance(data, dict):
        raise ConfigError(f"{path}: top level must be a mapping of keys")
    return data


def deep_merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    out = copy.deepcopy(base)
    for k, v in over.items():
        out[k] = deep_merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


def canonical_json(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"))


def digest(obj: Any) -> str:
    """SHA-256 of the canonical JSON of ``obj``: the identity of a science config subset."""
    return hashlib.sha256(canonical_json(obj).encode()).hexdigest()


def empirical_science(cfg: dict[str, Any], morphology: dict[str, Any]) -> dict[str, Any]:
    """The config subset that determines the empirical sweep's numbers."""
    from morphlearn.empirical.options import SweepOptions

    emp = cfg["empirical"]
    return {
        "model": "empirical",
        "positions_per_axis": cfg["grid"]["positions_per_axis"],
        "weights": emp["weights"],
        "designs": empirical_designs(cfg),
        "params": {**morphology, **emp.get("params", {})},
        # only when on, so that the digests of results made before the option existed still hold
        **({"mirror_derive": True} if emp.get("mirror_derive") else {}),
        **SweepOptions.from_config(emp).science(),
    }


def theory_science(cfg: dict[str, Any]) -> dict[str, Any]:
    """The config subset that determines the theory sweep's numbers (not sharding, threads)."""
    th = cfg["theory"]
    keys = ["r", "horizon", "success_radius", "integrator", "max_steps"]
    keys += ["rtol", "atol"] if th["integrator"] == "dp5" else ["dt"]
    return {
        "model": "theory",
        "grid": dict(cfg["grid"]),
        "theory": {k: th[k] for k in keys},
        "mirror_symmetry": cfg["sweep"]["mirror_symmetry"],
    }


@dataclass(frozen=True)
class LearnerSettings:
    """The ``learners`` section (config_schema.yaml), typed: real learners on the theory model."""

    enabled: bool
    learners: tuple[str, ...]
    protocols: tuple[str, ...]
    seeds: int
    seed: int
    budget: int
    cycles: int
    per_phase: int
    sigma0: float
    max_designs: int | None
    shards: int
    threads: int
    chunk: int
    bootstrap: int

    @classmethod
    def from_config(cls, cfg: dict[str, Any]) -> LearnerSettings:
        s = cfg["learners"]
        return cls(**{k: tuple(s[k]) if isinstance(s[k], list) else s[k] for k in cls.__dataclass_fields__})

    def science(self) -> dict[str, Any]:
        """What determines a design's learner numbers (not sharding, threads, batching, bootstrap)."""
        keep = ("learners", "protocols", "seeds", "seed", "budget", "cycles", "per_phase", "sigma0")
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items() if k in keep}


def learner_science(cfg: dict[str, Any]) -> dict[str, Any]:
    """The config subset that determines the learner stage's per-design numbers."""
    th = theory_science(cfg)
    grid = {"positions_per_axis": cfg["grid"]["positions_per_axis"]}
    return {"model": "learners", "theory": th["theory"], "grid": grid,
            "learners": LearnerSettings.from_config(cfg).science()}  # fmt: skip
