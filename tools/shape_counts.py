"""Counts of the architecture's shape (issue 23): run ``python tools/shape_counts.py``.

1. Model-name comparisons outside the registry: ``== "theory"`` and the like in src/, workflow/
   and notebooks/ (the same pattern as the project's before-stop hook).
2. Raw config reads below the edge: ``cfg[...]``, ``cfg.get(...)``, ``CFG[...]`` in the package,
   outside the edge: ``config.py`` (the schema), ``settings.py`` (the parse) and the models'
   ``parse`` methods, which configure.parse calls for each model's own section (AST-located).
3. Per shard, measured by running one: design grids built, body files read, settings parsed.
"""

from __future__ import annotations

import ast
import re
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

NAME_CMP = re.compile(
    r'(==|!=)\s*"(theory|empirical|mujoco)"|"(theory|empirical|mujoco)"\s*(==|!=)'
    r'|startswith\("(theory|empirical|mujoco)'
)
RAW_READ = re.compile(r"\bcfg\[|\bcfg\.get\(|\bCFG\[")
EDGE_FILES = {"config.py", "settings.py"}


def name_comparisons() -> list[str]:
    hits = []
    for folder, globs in (("src", ("*.py",)), ("workflow", ("*.py", "*.smk")), ("notebooks", ("*.ipynb",))):
        for g in globs:
            for p in sorted((ROOT / folder).rglob(g)):
                for i, line in enumerate(p.read_text().splitlines(), 1):
                    if NAME_CMP.search(line):
                        hits.append(f"{p.relative_to(ROOT)}:{i}: {line.strip()}")
    return hits


def _parse_methods(tree: ast.Module) -> list[range]:
    """Line ranges of ``parse`` methods of classes (the models' section parsers)."""
    out = []
    for cls in (n for n in ast.walk(tree) if isinstance(n, ast.ClassDef)):
        for f in cls.body:
            if isinstance(f, ast.FunctionDef) and f.name == "parse":
                out.append(range(f.lineno, (f.end_lineno or f.lineno) + 1))
    return out


def raw_reads() -> tuple[list[str], list[str]]:
    """(reads below the edge, reads inside model parse methods)."""
    below, edge = [], []
    for p in sorted((ROOT / "src/morphlearn").rglob("*.py")):
        if p.name in EDGE_FILES and p.parent.name == "morphlearn":
            continue
        text = p.read_text()
        spans = _parse_methods(ast.parse(text))
        for i, line in enumerate(text.splitlines(), 1):
            if RAW_READ.search(line):
                where = edge if any(i in r for r in spans) else below
                where.append(f"{p.relative_to(ROOT)}:{i}: {line.strip()}")
    return below, edge


def per_shard() -> dict[str, int]:
    """Run one smoke shard of each model with counters on what the redesign builds once."""
    from morphlearn import config, configure, grid, rules, settings
    from morphlearn.physics import params

    counts = {"design grids built": 0, "body files read": 0, "settings parsed": 0}
    real_post, real_load, real_parse = grid.DesignGrid.__post_init__, params.load_params, configure.parse

    def post(self: grid.DesignGrid) -> None:
        counts["design grids built"] += 1
        real_post(self)

    def load(path: str | Path) -> params.EmpiricalParams:
        counts["body files read"] += 1
        return real_load(path)

    def parse(cfg: dict) -> settings.Settings:
        counts["settings parsed"] += 1
        return real_parse(cfg)

    grid.DesignGrid.__post_init__ = post  # type: ignore[method-assign]
    params.load_params = load
    import morphlearn.physics.model as plugin

    plugin.load_params = load
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        raw = config.deep_merge(
            config.read(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"]), {"results_dir": tmp, "design_cache": False}
        )
        for model in ("theory", "empirical"):
            for k in counts:
                counts[k] = 0
            s = parse(raw)  # as a rule script's entry does
            rules.run_shard(s, model, 0, Path(tmp) / f"{model}.nc")
            out |= {f"{model}: {k}": v for k, v in counts.items()}
    return out


def main() -> int:
    cmp = name_comparisons()
    below, edge = raw_reads()
    print(f"model-name comparisons outside the registry: {len(cmp)}")
    for h in cmp:
        print(f"  {h}")
    print(f"raw config reads below the edge: {len(below)}")
    for h in below:
        print(f"  {h}")
    print(f"  (inside the models' parse methods, which are the edge for their own sections: {len(edge)})")
    for k, v in per_shard().items():
        print(f"per shard, {k}: {v}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
