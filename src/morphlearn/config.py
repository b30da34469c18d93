"""Configuration as data: schema validation with one-line errors, defaults, reading and merging
YAML files, hashing of config subsets. :mod:`morphlearn.settings` parses the result into types;
each model checks its own section (:meth:`morphlearn.models.Model.parse`)."""

from __future__ import annotations

import copy
import hashlib
import json
import math
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
    errors = sorted(jsonschema.Draft202012Validator(sch).iter_errors(cfg), key=lambda e: list(e.absolute_path))
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
        raise ConfigError(
            f"{key} = {obj!r} is not a finite number; allowed: finite numbers in the range the schema gives"
        )


def _check_results_dir(rd: str) -> None:
    p = Path(rd)
    if p.resolve() == Path(p.resolve().anchor):
        raise ConfigError(
            f"results_dir = {rd!r} is the file-system root; allowed: a non-empty path "
            "other than '/' (default 'results')"
        )
    if p.exists() and not p.is_dir():
        raise ConfigError(f"results_dir = {rd!r} is an existing file; allowed: a folder (or a new path)")


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
        raise ConfigError(
            f"theory.success_radius = {th['success_radius']} is not below theory.r = "
            f"{th['r']}; allowed: < {th['r']} (the robot would start inside the light)"
        )
    need = math.ceil(th["horizon"] / th["dt"])
    if th["integrator"] == "rk4" and th["max_steps"] < need:  # the cap would cut every trajectory short
        raise ConfigError(
            f"theory.max_steps = {th['max_steps']} is below the {need} steps that theory.integrator "
            f"= rk4 takes (horizon / dt); allowed: max_steps >= {need}, or a larger dt"
        )


def _check_cross(cfg: dict[str, Any]) -> None:
    """Checks across keys that need no design grid or file (those are the settings' and each
    model's: :func:`morphlearn.settings.parse`)."""
    _check_results_dir(cfg["results_dir"])
    th = cfg["theory"]
    _check_analysis(cfg["analysis"], th)
    if cfg.get("render_only") and not (cfg["figures"]["enabled"] and th.get("enabled", True)):
        raise ConfigError(
            "render_only = true needs figures.enabled and theory.enabled; allowed: render_only = false or both enabled"
        )


def read(path: str | Path, overrides: list[str | Path] = ()) -> dict[str, Any]:
    """Read a YAML config, deep-merging override files as ``--configfile`` does (not validated)."""
    cfg = _read_yaml(path)
    for o in overrides:
        cfg = deep_merge(cfg, _read_yaml(o))
    return cfg


def load(path: str | Path, overrides: list[str | Path] = ()) -> dict[str, Any]:
    """:func:`read` and :func:`validate`: the validated mapping (``settings.load`` types it)."""
    return validate(read(path, overrides))


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
