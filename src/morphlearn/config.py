"""Configuration as data: schema validation with one-line errors, defaults, reading and merging
YAML files, hashing of config subsets. :mod:`morphlearn.settings` parses the result into types;
each model checks its own section (:meth:`morphlearn.models.Model.parse`)."""

from __future__ import annotations

import copy
import hashlib
import json
import math
import os
import sys
import tempfile
from collections.abc import Mapping, Sequence
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any

import yaml

from morphlearn import bounded

# jsonschema imports rfc3987_syntax when it is installed (jupyter-events pulls it in), and that
# import builds 39 lark grammars: about 2 CPU-s in every process that validates a config (the
# Snakefile's parse and every rule job), for an "iri" format this schema does not use and whose
# check jsonschema skips when the import fails. So the import fails here, for this import only.
_blocked = "rfc3987_syntax" not in sys.modules
if _blocked:
    sys.modules["rfc3987_syntax"] = None  # type: ignore[assignment]
try:
    import jsonschema
finally:
    if _blocked:
        del sys.modules["rfc3987_syntax"]


class ConfigError(ValueError):
    """A bad configuration value; the message names the key and what is allowed."""


def _strict_integer(_: Any, instance: Any) -> bool:
    """JSON Schema counts 5.0 as an integer; here an integer is an int (``grid.weights: 5.0``
    crashed a shard, ``max_steps: 10000.0`` changed the science digest). bool is not one."""
    return isinstance(instance, int) and not isinstance(instance, bool)


#: Draft 2020-12 with integers that are ints.
_Validator = jsonschema.validators.extend(
    jsonschema.Draft202012Validator,
    type_checker=jsonschema.Draft202012Validator.TYPE_CHECKER.redefine("integer", _strict_integer),
)


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
        extra = sorted(str(k) for k in set(err.instance) - set(allowed))
        where = "" if key == "<top level>" else f" under '{key}'"
        # at most a few named, each cut short: 100,000 unknown keys once made a 989 KB line
        named = [k if len(k) <= 40 else f"{k[:30]}...({len(k)} chars)" for k in extra[:5]]
        more = f" and {len(extra) - 5} more" if len(extra) > 5 else ""
        return f"unknown key{'s' if len(extra) > 1 else ''} {named}{more}{where}; allowed: {allowed}"
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
    # a schema of alternatives (oneOf: empirical.designs) has no type: its description says what
    desc = " ".join(str(s.get("description", "")).split()).split(". ")[0].rstrip(".")
    kind = s.get("type") or desc or "see config_schema.yaml"
    allowed = f"; allowed: {kind} {' and '.join(bounds)}".rstrip()
    if v == "type" and isinstance(err.instance, str) and len(err.absolute_path) > 1:
        # Snakemake's --config 'grid={weights: 7}' gives {"grid": {"weights": "7"}}: nested values stay strings
        allowed += (
            " (Snakemake passes the values inside a nested --config value, like grid={weights: 7}, as "
            "strings: give them in a --configfile YAML instead)"
        )
    value, why = repr(err.instance), err.message
    value = value if len(value) <= 80 else f"{value[:60]}... ({len(value)} characters)"
    why = why if len(why) <= 160 else f"{why[:140]}..."
    return f"{key} = {value} is invalid ({why}){allowed}"


def _fill_defaults(cfg: dict[str, Any], sch: dict[str, Any]) -> None:
    for k, sub in sch.get("properties", {}).items():
        if k not in cfg and "default" in sub:
            cfg[k] = copy.deepcopy(sub["default"])
        if isinstance(cfg.get(k), dict) and sub.get("type") == "object":
            _fill_defaults(cfg[k], sub)


def validate(
    cfg: dict[str, Any], path_keys: Sequence[str] = (), sections: Mapping[str, str] = MappingProxyType({})
) -> dict[str, Any]:
    """Validate a config mapping; return a copy with defaults filled. Raises ConfigError.
    ``path_keys``: the models' path keys (``section.key``) checked besides :data:`PATH_KEYS`;
    ``sections``: a model's section the schema lacks -> the section whose schema it shares (an
    engine on the physics base takes the physics section's keys without a schema entry)."""
    if not isinstance(cfg, dict):
        raise ConfigError(f"config must be a mapping, got {type(cfg).__name__}")
    _check_finite(cfg, "")
    sch = schema()
    for name, like in sections.items():
        sch["properties"].setdefault(name, copy.deepcopy(sch["properties"][like]))
    errors = sorted(_Validator(sch).iter_errors(cfg), key=lambda e: list(e.absolute_path))
    if errors:
        raise ConfigError(_describe(errors[0]))
    out = copy.deepcopy(cfg)
    _fill_defaults(out, sch)
    _check_cross(out, path_keys)
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
    # before the schema, whose messages print the value whole: Python refuses to print an integer
    # of more than 4,300 digits (a ValueError out of the validator), and a 1 MB string made a 1 MB line
    elif isinstance(obj, int) and not isinstance(obj, bool) and obj.bit_length() > 64:
        raise ConfigError(
            f"{key} = an integer of {obj.bit_length()} bits; allowed: integers of at most 64 bits in the range "
            "the schema gives"
        )
    elif isinstance(obj, str) and len(obj) > MAX_STRING:
        raise ConfigError(f"{key} = {obj[:30]!r}... is {len(obj)} characters long; allowed: at most {MAX_STRING}")


#: The longest string a config value may be (a path is at most 4,096 bytes on Linux).
MAX_STRING = 4096


#: Characters a path key may not hold: Snakemake reads braces in input/output paths as wildcards.
UNSAFE_PATH_CHARS = "{}"
#: Path keys that become Snakemake input or output paths (``scenario_file`` is read by Python only);
#: each model declares its own (``Model.path_keys``), passed to :func:`validate`.
PATH_KEYS = (
    "results_dir",
    "bundle_dir",
    "survey_from.bundle",
    "screen_from.bundle",
    "screen_from.refinement",
    "engines.pybullet",
    "engines.mujoco",
    "engines.theory",
)


def check_path(key: str, value: str | None) -> None:
    """Refuse at start a path Snakemake cannot hold as a file name (braces: a WildcardError after
    the config is read) or that holds a line break (no log line or shell command can quote it)."""
    if value is None:
        return
    bad = sorted({c for c in value if c in UNSAFE_PATH_CHARS or c in "\n\r\x00"})
    if bad:
        raise ConfigError(
            f"{key} = {value!r} holds {' and '.join(repr(c) for c in bad)}; allowed: a path without "
            "'{', '}' (Snakemake reads them as wildcards), line breaks or NUL"
        )


def _check_paths(cfg: dict[str, Any], path_keys: Sequence[str]) -> None:
    for key in (*PATH_KEYS, *path_keys):
        sec, _, name = key.rpartition(".")
        holder = cfg.get(sec, {}) if sec else cfg
        value = holder.get(name) if isinstance(holder, dict) else None
        check_path(key, value if isinstance(value, str) else None)


#: The project's own folders (relative to the project folder, where every run starts): no run
#: writes results or a bundle into them or below them.
SOURCE_FOLDERS = ("benchmarks", "config", "docs", "envs", "notebooks", "profiles", "src", "tests", "tools", "workflow")
#: Where results may go, for the messages that refuse a folder.
RESULTS_ALLOWED = (
    "a folder of your own under results/ that is not a bundle, reached without a link out of results/ and "
    "without a hidden folder (e.g. results/my-run; default 'results'), or one under the system's temporary folder"
)


def _is_file(p: Path) -> bool:
    try:
        return p.is_file()
    except OSError:  # a name too long for the file system: nothing is there
        return False


def source_folder(path: str | Path) -> str | None:
    """Why ``path`` is no place for a run's output (None when it may be): it is the project
    folder, one that holds it, or one of the project's source folders or inside one. Shared by
    the ``results_dir`` and the ``bundle_dir`` guards (:func:`morphlearn.bundles.make.check_target`)."""
    target, here = Path(path).resolve(), Path.cwd().resolve()
    if target in (here, *here.parents):
        return "is the project folder or one that holds it"
    for name in SOURCE_FOLDERS:
        if target.is_relative_to(here / name):
            return f"is {'' if target == here / name else 'inside '}the project's source folder {name}/"
    return None


def bundle_holding(path: str | Path) -> Path | None:
    """The results bundle (a folder with ``bundle.json``) that ``path`` is or lies inside; None."""
    target = Path(path).resolve()
    return next((d for d in (target, *target.parents) if _is_file(d / "bundle.json")), None)


#: The name of the working copy a re-render of a bundle renders into, beside it
#: (:func:`morphlearn.bundles.render.rendered_copy`): the one hidden folder a run may write, and
#: only as a render_only run with the bundle's own configs.
RERENDER_PREFIX = ".rerender-"


def place_refusal(path: str | Path, *, rerender: bool = False) -> str | None:
    """Why ``path`` is no place to write (None when it may be), bundles aside: the project folder
    or one that holds it, a source folder or inside one (:func:`source_folder`), a path with a
    hidden part (``.git``, ``.venv``, ``.snakemake``; ``rerender``: but a re-render's working copy
    ``results/.rerender-*``), a link out of ``results/``, or anywhere outside the project's
    ``results/`` folder but the system's temporary folder (scratch and tests, outside the project).
    The project is the folder the command runs in, as for every path of a config."""
    p = Path(path)
    why = source_folder(p)
    if why:
        return why
    here = Path.cwd().resolve()
    results = (here / "results").resolve()
    target = p.resolve()
    spelled = Path(os.path.normpath(here / p))  # as written, links not followed
    parts = list(p.parts if not p.is_absolute() else ())
    for base in (results, Path(tempfile.gettempdir()).resolve()):
        if target.is_relative_to(base):
            parts += target.relative_to(base).parts
            break
    hidden = [x for x in parts if x.startswith(".") and x not in (".", "..")]
    for x in hidden:
        ok = rerender and x.startswith(RERENDER_PREFIX) and target.parent == results
        if not ok:
            return f"has the hidden folder {x!r} in it (.git, .venv, .snakemake and the like are no place for results)"
    if target == results or target.is_relative_to(results):
        return None
    if spelled.is_relative_to(here / "results"):
        return f"is a symbolic link out of results/ (to {target})"
    if not target.is_relative_to(here) and target.is_relative_to(Path(tempfile.gettempdir()).resolve()):
        return None
    return f"is outside the project's results/ folder ({target})"


def write_refusal(path: str | Path, *, rerender: bool = False, configs: Sequence[str] | None = None) -> str | None:
    """Why nothing may write to ``path`` (None when it may): the one guard of every writer (a run's
    ``results_dir``, ``bundle_dir`` and the scenario bundles).
    Refused: what :func:`place_refusal` refuses, and a results bundle or a folder inside one, but
    for a ``rerender``: a render_only run that re-makes the bundle at ``path`` itself, with the
    config files ``configs`` its bundle.json records (None: not known yet, at config load; the
    workflow's start checks them, :func:`check_results_dir`)."""
    why = source_folder(path)
    if why:
        return why
    target = Path(path).resolve()
    held = bundle_holding(target)
    if held is None:
        return place_refusal(path, rerender=rerender)
    if not (rerender and held == target):
        where = "holds a results bundle" if held == target else f"is inside the results bundle {held}"
        return f"{where} (bundle.json), which it would write into"
    if configs is None:
        return place_refusal(path, rerender=rerender)
    try:
        recorded = bounded.json_file(held / "bundle.json").get("made_by", {}).get("configs")
    except (ValueError, AttributeError):
        recorded = None
    given = sorted({os.path.normpath(c) for c in configs})
    if not isinstance(recorded, list) or given != sorted({os.path.normpath(str(c)) for c in recorded}):
        extra = [c for c in recorded or [] if Path(str(c)).name != "config.yaml"] if isinstance(recorded, list) else []
        return (
            f"holds a results bundle made by configs {recorded}, but this render_only run was given {given}: it "
            "would re-render the bundle with the wrong config"
            + (f" (give --configfile {' '.join(map(str, extra))}, as morphlearn render does)" if extra else "")
        )
    return place_refusal(path, rerender=rerender)


def check_results_dir(rd: str, render_only: bool = False, configs: Sequence[str] | None = None) -> None:
    """A run's ``results_dir`` against the write guard (:func:`write_refusal`): ConfigError naming
    it and what is allowed. ``configs``: the run's config files, where known (the workflow's start:
    a render_only run re-renders a bundle only with the configs it records)."""
    p = Path(rd)
    if p.resolve() == Path(p.resolve().anchor):
        raise ConfigError(
            f"results_dir = {rd!r} is the file-system root; allowed: a non-empty path "
            "other than '/' (default 'results')"
        )
    if p.exists() and not p.is_dir():
        raise ConfigError(f"results_dir = {rd!r} is an existing file; allowed: a folder (or a new path)")
    why = write_refusal(p, rerender=render_only, configs=configs)
    if why is None:
        return
    if "results bundle" in why:
        # render_only re-renders exactly the bundle named with its own configs (its documented
        # command); any other run would write shards, stores and tables into it (issues 38, 57)
        raise ConfigError(
            f"results_dir = {rd!r} {why}; allowed: render_only=True with results_dir the bundle itself and "
            f"its own configs to re-render it, or {RESULTS_ALLOWED}"
        )
    raise ConfigError(f"results_dir = {rd!r} {why}; allowed: {RESULTS_ALLOWED}")


def _check_results_dir(rd: str, render_only: bool = False) -> None:
    check_results_dir(rd, render_only)


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


def _check_cross(cfg: dict[str, Any], path_keys: Sequence[str]) -> None:
    """Checks across keys that need no design grid or file (those are the settings' and each
    model's: :func:`morphlearn.configure.parse`)."""
    _check_paths(cfg, path_keys)
    _check_results_dir(cfg["results_dir"], bool(cfg.get("render_only")))
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
    """:func:`read` and :func:`validate`: the validated mapping (``configure.load`` types it)."""
    return validate(read(path, overrides))


class _DuplicateKey(yaml.constructor.ConstructorError):
    pass


#: PyYAML's safe loader on libyaml's C parser where it is built (it is in the pinned PyYAML wheels):
#: about 20 times faster than the pure-Python one (a file of 100,000 keys took 22 s to read).
_SafeLoader: type = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class _UniqueKeyLoader(_SafeLoader):  # type: ignore[misc,valid-type]
    """PyYAML keeps the last of two equal keys silently: a key given twice is refused."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
        seen: dict[Any, yaml.Mark] = {}
        for key_node, _ in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":  # '<<: *anchor' merges are overrides by design
                continue
            key = self.construct_object(key_node, deep=True)
            try:
                first = seen.setdefault(key, key_node.start_mark)
            except TypeError:  # an unhashable key: the base class says so
                continue
            if first is not key_node.start_mark:
                raise _DuplicateKey(
                    None,
                    None,
                    f"key {key!r} given twice (lines {first.line + 1} and {key_node.start_mark.line + 1})",
                    key_node.start_mark,
                )
        return super().construct_mapping(node, deep)


def yaml_mapping(path: str | Path, what: str = "config keys") -> dict[str, Any]:
    """A YAML file whose top level is a mapping with unique keys. Every way it can be bad
    (unreadable, not UTF-8 text, malformed, a key twice, empty, another shape, beyond the limits of
    :mod:`morphlearn.bounded`: its size, nesting, aliases) raises ValueError with one line saying
    what, without the path (the caller names the file or the key)."""
    raw = bounded.read_bytes(path)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ValueError(
            f"not a UTF-8 text file (byte 0x{raw[e.start]:02x} at offset {e.start}); allowed: a YAML mapping of {what}"
        ) from None
    if "\x00" in text:
        raise ValueError(
            f"not a text file (NUL byte at offset {text.index(chr(0))}); allowed: a YAML mapping of {what}"
        )
    try:
        bounded.check_yaml(text, _UniqueKeyLoader)  # before the composer, which recurses per level
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # a safe loader
    except yaml.reader.ReaderError as e:
        raise ValueError(
            f"not a text file (control character at offset {e.position}); allowed: a YAML mapping of {what}"
        ) from None
    except _DuplicateKey as e:
        raise ValueError(f"{e.problem}; allowed: each key once (YAML would keep the last value silently)") from None
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        raise ValueError(
            "malformed YAML" + (f" at line {mark.line + 1}, column {mark.column + 1}" if mark else "")
        ) from None
    if data is None:
        raise ValueError(f"empty (no keys); allowed: a YAML mapping of {what}")
    if not isinstance(data, dict):
        kind = {"list": "a list", "str": "a string", "int": "a number", "float": "a number", "bool": "true/false"}
        raise ValueError(
            f"top level is {kind.get(type(data).__name__, type(data).__name__)}, not a mapping; "
            f"allowed: a YAML mapping of {what}"
        )
    return data


def _read_yaml(path: str | Path) -> dict[str, Any]:
    try:
        return yaml_mapping(path)
    except ValueError as e:
        raise ConfigError(f"{path}: {e}") from None


def check_start(basedir: str | Path, configfiles: list[str | Path]) -> None:
    """The workflow's first check, before Snakemake reads ``config.yaml``: it runs from its own
    folder (``config.yaml``, ``config/``, ``notebooks/`` and ``src/`` are read relative to the
    working directory; from elsewhere a missing config.yaml was skipped silently and the schema
    then named a missing key), and each config file is a YAML mapping with each key once
    (Snakemake keeps the last of two equal keys silently). Raises ConfigError."""
    here, root = Path.cwd().resolve(), Path(basedir).resolve()
    if here != root:
        raise ConfigError(
            f"the workflow runs from its own folder {root} (config.yaml, config/, notebooks/ and src/ "
            f"are read relative to the working directory), not from {here}; allowed: cd {root} first "
            f"(or snakemake --directory {root})"
        )
    check_files(configfiles)


def check_files(configfiles: list[str | Path]) -> None:
    """Each config file a YAML mapping with each key once, or one ConfigError naming it."""
    for f in configfiles:
        _read_yaml(f)


def deep_merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    out = copy.deepcopy(base)
    for k, v in over.items():
        out[k] = deep_merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


def flatten(obj: Any, prefix: str = "") -> dict[str, Any]:
    """Nested mappings as one mapping of dotted keys (``{"a": {"b": 1}}`` -> ``{"a.b": 1}``), to
    name the first key where two configs differ."""
    if not isinstance(obj, dict) or not obj:
        return {prefix: obj}
    out: dict[str, Any] = {}
    for k, v in obj.items():
        out |= flatten(v, f"{prefix}.{k}" if prefix else str(k))
    return out


def canonical_json(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"))


def digest(obj: Any) -> str:
    """SHA-256 of the canonical JSON of ``obj``: the identity of a science config subset."""
    return hashlib.sha256(canonical_json(obj).encode()).hexdigest()
