"""Write config/README.md, the table of every config key, from src/morphlearn/config_schema.yaml.

Run after changing the schema: ``python tools/config_docs.py``; tests/test_release.py checks that
the committed file is what this prints.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = ROOT / "src/morphlearn/config_schema.yaml"
OUT = ROOT / "config/README.md"


#: The JSON Schema keywords the schema uses. Any other key is a typo or an unquoted comma in a flow
#: mapping (``{description: a, b}`` makes a key ``b``): the description is cut short and the key
#: is silently ignored by the validator.
KEYWORDS = frozenset(
    "$schema type additionalProperties required properties default description minimum maximum "
    "exclusiveMinimum exclusiveMaximum minLength enum const items minItems maxItems minProperties uniqueItems "
    "oneOf anyOf".split()
)


def unknown_keywords(s: Any, where: str = "") -> list[str]:
    """'key: keyword' for every key of a (sub)schema that is not a JSON Schema keyword."""
    if not isinstance(s, dict):
        return []
    out = [f"{where or '<top level>'}: {k!r}" for k in s if k not in KEYWORDS]
    for k, sub in s.get("properties", {}).items():
        out += unknown_keywords(sub, f"{where}.{k}" if where else k)
    for key in ("items",):
        out += unknown_keywords(s.get(key), f"{where}[]")
    for key in ("oneOf", "anyOf"):
        for i, sub in enumerate(s.get(key, [])):
            out += unknown_keywords(sub, f"{where}.{key}[{i}]")
    return out


def _allowed(s: dict[str, Any]) -> str:
    parts = []
    if "enum" in s:
        parts.append("one of " + ", ".join(f"`{v}`" for v in s["enum"]))
    for key, op in (("minimum", ">="), ("exclusiveMinimum", ">"), ("maximum", "<="), ("exclusiveMaximum", "<")):
        if key in s:
            parts.append(f"{op} {s[key]}")
    if "oneOf" in s or "anyOf" in s:
        parts.append(" or ".join(_kind(o) for o in s.get("oneOf", s.get("anyOf"))))
    return "; ".join(parts)


def _kind(s: dict[str, Any]) -> str:
    if "const" in s:
        return f"`{json.dumps(s['const'])}`"
    if "enum" in s and "type" not in s:
        return "enum"
    t = s.get("type", "")
    return "/".join(t) if isinstance(t, list) else t


def _cell(text: Any) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def rows(schema: dict[str, Any], prefix: str = "") -> list[str]:
    out = []
    required = set(schema.get("required", []))
    for key, s in schema.get("properties", {}).items():
        name = f"{prefix}{key}"
        default = f"`{json.dumps(s['default'])}`" if "default" in s else ("required" if key in required else "")
        out.append(
            f"| `{name}` | {_kind(s)} | {_cell(_allowed(s))} | {_cell(default)} | {_cell(s.get('description', ''))} |"
        )
        if s.get("type") == "object" and "properties" in s:
            out += rows(s, f"{name}.")
    return out


def render() -> str:
    schema = yaml.safe_load(SCHEMA.read_text())
    bad = unknown_keywords(schema)
    if bad:
        raise ValueError(f"{SCHEMA.name}: not JSON Schema keywords (an unquoted comma?): {'; '.join(bad)}")
    return "\n".join(
        [
            "# Configuration keys",
            "",
            "Generated from `src/morphlearn/config_schema.yaml` by `tools/config_docs.py`: do not edit by",
            "hand. `config.yaml` is the default (reduced) sweep; the presets in this folder override it",
            "(`snakemake --configfile config/full.yaml`); `full.yaml` and `gpu.yaml` write to their own `results_dir`.",
            "",
            "| key | type | allowed | default | meaning |",
            "|---|---|---|---|---|",
            *rows(schema),
            "",
        ]
    )


def main() -> int:
    text = render()
    if "--check" in sys.argv[1:]:
        current = OUT.read_text() if OUT.exists() else ""
        if current != text:
            print(f"{OUT.relative_to(ROOT)} is out of date: run python tools/config_docs.py", file=sys.stderr)
            return 1
        return 0
    OUT.write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
